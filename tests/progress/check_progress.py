#!/usr/bin/env python3
"""Checks rtuscope's progress line through a real pseudo-terminal, as a user sees it.

Usage: check_progress.py RTUSCOPE WORK_DIR report|decode|export|error

A text hex capture of a few MB (more on a fast build: each pass must run long enough to
show a rate) is generated in WORK_DIR and removed at the end. With stderr on a pty the command
must draw progress lines ('\\r'-separated) whose percentages never go back within a pass,
never exceed 100 and reach 100 for every pass, and must erase the line at the end. With
--quiet, with stderr on a pipe, and for a small capture there must be no such line. Stdout
(and for export the output file) must be byte-identical in every case.
"""
import fcntl
import os
import re
import struct
import subprocess
import sys
import termios
import threading
import time
import tty

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail  # noqa: E402  (after the path line)

ERASE = b"\r\x1b[K"
PROGRESS = re.compile(rb"([a-z]+ (?:[12]/2|1/1))\s+(\d+)%\s+(\S+) MB/s\s+(\S+) rec/s\s+ETA (\S+)")
BIG_SIZE = 5 * 1024 * 1024  # over the 4 MB below which no line is shown
MIN_TWO_PASSES_S = 1.5  # the two passes of a report over the big capture, at least
MAX_SIZE = 400 * 1024 * 1024


def crc16(data):
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return bytes([crc & 0xFF, crc >> 8])


def frame(adu):
    return adu + crc16(adu)


def write_capture(path, min_size, damaged=False):
    """Polls of three slaves (FC3, ten registers), answered 8 ms later, every 50 ms."""
    # The values repeat every 256 polls, so each distinct frame is built (and its CRC
    # computed) once: a capture of a few hundred MB is written in seconds.
    period = 3 * 256
    exchanges = []
    for i in range(period):
        slave = 1 + i % 3
        request = frame(bytes([slave, 3, 0, 0, 0, 10]))
        values = b"".join(((i + k) % 65536).to_bytes(2, "big") for k in range(10))
        response = frame(bytes([slave, 3, 20]) + values)
        exchanges.append((request.hex(" ").upper(), response.hex(" ").upper()))
    lines = ["# baud=9600 parity=E stop=1\n"]
    size = len(lines[0])
    t_us = 0
    i = 0
    while size < min_size:
        for delay_us, adu in zip((0, 8000), exchanges[i % period]):
            t = t_us + delay_us
            line = f"{1700000000 + t // 1000000}.{t % 1000000:06d} {adu}\n"
            lines.append(line)
            size += len(line)
        t_us += 50000
        i += 1
    if damaged:
        lines.append("this is not a capture line\n")
    with open(path, "w", encoding="ascii") as out:
        out.writelines(lines)


def run(cmd, stderr_tty, columns=120):
    """Runs cmd; returns (returncode, stdout, stderr bytes). stderr on a raw pty when asked."""
    if not stderr_tty:
        result = subprocess.run(cmd, capture_output=True, stdin=subprocess.DEVNULL, check=False)
        return result.returncode, result.stdout, result.stderr
    master, slave = os.openpty()
    tty.setraw(slave)  # no "\n" → "\r\n": the bytes exactly as written
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, columns, 0, 0))
    proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=slave)
    os.close(slave)
    chunks = []

    def drain():
        while True:
            try:
                data = os.read(master, 65536)
            except OSError:  # EIO: the child closed the terminal
                return
            if not data:
                return
            chunks.append(data)

    reader = threading.Thread(target=drain)
    reader.start()
    stdout = proc.stdout.read()
    proc.wait()
    reader.join()
    os.close(master)
    return proc.returncode, stdout, b"".join(chunks)


def progress_lines(stderr):
    """(label, percent, MB/s, rec/s, ETA) of every progress line drawn."""
    return [m.groups() for m in PROGRESS.finditer(stderr)]


def check_shown(stderr, labels, columns=120, passes=2):
    """The passes in `labels` each went 0..100 in order, and the line was erased at the end.
    `passes`: 1 where the survey runs alongside the decoding (a capture declaring its settings)."""
    drawn = progress_lines(stderr)
    if not drawn:
        fail(f"no progress line on the terminal: {stderr[:300]!r}")
    order = []
    for label, *_ in drawn:
        if not order or order[-1] != label:
            order.append(label)
    expected = [f"{name} {n}/{passes}".encode() for name in labels for n in range(1, passes + 1)]
    if order != expected:
        fail(f"passes drawn in the order {order}, expected {expected}")
    for label in expected:
        percents = [int(p) for lab, p, *_ in drawn if lab == label]
        if percents != sorted(percents):
            fail(f"{label}: progress went back: {percents}")
        if max(percents) > 100:
            fail(f"{label}: above 100%: {percents}")
        if percents[-1] != 100:
            fail(f"{label}: ended at {percents[-1]}%, not 100%")
    # Every line was drawn in place: after a carriage return, within the terminal's width.
    for piece in stderr.split(b"\r"):
        text = piece.replace(b"\x1b[K", b"")
        if PROGRESS.search(text) and len(text) >= columns:
            fail(f"progress line of {len(text)} columns on a {columns}-column terminal")
        if b"\n" in piece and PROGRESS.search(piece):
            fail(f"a progress line ended with a newline: {piece!r}")
    # Some line showed real rates once the pass had run a while.
    if not any(mbs != b"--" and eta != b"--:--" for _, _, mbs, _, eta in drawn):
        fail("no progress line with a rate and an ETA")
    return drawn


def check_absent(stderr, why):
    if PROGRESS.search(stderr) or b"\r" in stderr or b"\x1b[" in stderr or b"%" in stderr:
        fail(f"{why}: progress output on stderr: {stderr[:300]!r}")


def expect_ok(result, what):
    code, _, stderr = result
    if code != 0:
        fail(f"{what} exited {code}: {stderr[-500:]!r}")
    return result


def main():
    if len(sys.argv) != 4:
        fail(__doc__)
    rtuscope, work, check = sys.argv[1:]
    os.makedirs(work, exist_ok=True)
    big = os.path.join(work, "big.hex")
    small = os.path.join(work, "small.hex")
    write_capture(big, BIG_SIZE, damaged=check == "error")
    if check != "error":
        # A rate and an ETA are drawn once a pass has run a while: the capture grows until
        # each pass takes long enough on this build and machine.
        started = time.monotonic()
        subprocess.run([rtuscope, "report", big, "--no-identify", "-q", "-o", os.devnull],
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
        elapsed = time.monotonic() - started
        if elapsed < MIN_TWO_PASSES_S:
            size = min(int(BIG_SIZE * 1.3 * MIN_TWO_PASSES_S / max(elapsed, 0.01)), MAX_SIZE)
            write_capture(big, size)
    write_capture(small, 200 * 1024)

    if check == "report":
        cmd = [rtuscope, "report", big]
        _, out_tty, err_tty = expect_ok(run(cmd, True), "report on a terminal")
        # Identification reads a bounded sample between the passes, without a line of its own.
        check_shown(err_tty, ["decoding"])
        if not err_tty.endswith(ERASE):
            fail(f"progress line not erased at the end: {err_tty[-100:]!r}")
        _, out_quiet, err_quiet = expect_ok(run(cmd + ["--quiet"], True), "report --quiet")
        check_absent(err_quiet, "--quiet")
        _, out_pipe, err_pipe = expect_ok(run(cmd, False), "report to a pipe")
        check_absent(err_pipe, "stderr on a pipe")
        if not out_tty or out_tty != out_quiet or out_tty != out_pipe:
            fail("report's stdout differs between terminal, --quiet and pipe runs")
        _, _, err_small = expect_ok(run([rtuscope, "report", small], True), "small report")
        check_absent(err_small, "a capture under 4 MB")
        # A narrow terminal: the line is cut, never wrapped.
        _, out_narrow, err_narrow = expect_ok(run(cmd + ["--no-identify"], True, columns=40),
                                              "report on 40 columns")
        if b"decoding 2/2" not in err_narrow:
            fail(f"no progress on a 40-column terminal: {err_narrow[:200]!r}")
        for piece in err_narrow.split(b"\r"):
            if len(piece.replace(b"\x1b[K", b"")) >= 40:
                fail(f"line of {len(piece)} columns on a 40-column terminal: {piece!r}")
    elif check == "decode":
        cmd = [rtuscope, "decode", big, "--format", "jsonl"]
        _, out_tty, err_tty = expect_ok(run(cmd, True), "decode on a terminal")
        check_shown(err_tty, ["decoding"])
        if not err_tty.endswith(ERASE):
            fail(f"progress line not erased at the end: {err_tty[-100:]!r}")
        _, out_quiet, err_quiet = expect_ok(run(cmd + ["-q"], True), "decode -q")
        check_absent(err_quiet, "-q")
        _, out_pipe, err_pipe = expect_ok(run(cmd, False), "decode to a pipe")
        check_absent(err_pipe, "stderr on a pipe")
        if out_tty.count(b"\n") < 10000 or out_tty != out_quiet or out_tty != out_pipe:
            fail("decode's stdout differs between terminal, --quiet and pipe runs")
    elif check == "export":
        outputs = []
        for name, extra, on_tty in (("tty", [], True), ("quiet", ["--quiet"], True),
                                    ("pipe", [], False)):
            path = os.path.join(work, f"{name}.pcapng")
            _, stdout, stderr = expect_ok(
                run([rtuscope, "export", big, "-o", path] + extra, on_tty), f"export ({name})")
            summary = f"rtuscope: {path}: ".encode()
            if name == "tty":
                check_shown(stderr, ["exporting"])
                # The summary starts on a cleared line, after the progress line is erased.
                if ERASE + summary not in stderr:
                    fail(f"summary not on a cleared line: {stderr[-300:]!r}")
                stderr = stderr[stderr.rindex(ERASE) + len(ERASE):]
            else:
                check_absent(stderr, name)
            if not stderr.startswith(summary) or stderr.count(b"\n") != 1:
                fail(f"export ({name}) stderr: {stderr!r}")
            with open(path, "rb") as f:
                outputs.append((stdout, f.read()))
        if len(outputs[0][1]) < 100000 or any(o != outputs[0] for o in outputs):
            fail("export's output differs between terminal, --quiet and pipe runs")
    elif check == "native":
        # The raw export declares its settings: report and export read it once, their survey
        # alongside, and show that one pass as 1/1.
        native = os.path.join(work, "native.pcapng")
        expect_ok(run([rtuscope, "export", big, "--raw", "-o", native, "-q"], False),
                  "export --raw")
        cmd = [rtuscope, "report", native, "--no-identify"]
        _, out_tty, err_tty = expect_ok(run(cmd, True), "report of a raw export on a terminal")
        check_shown(err_tty, ["decoding"], passes=1)
        if not err_tty.endswith(ERASE):
            fail(f"progress line not erased at the end: {err_tty[-100:]!r}")
        _, out_pipe, err_pipe = expect_ok(run(cmd, False), "report of a raw export to a pipe")
        check_absent(err_pipe, "stderr on a pipe")
        if not out_tty or out_tty != out_pipe:
            fail("report's stdout differs between terminal and pipe runs")
        again = os.path.join(work, "again.pcapng")
        _, _, err_export = expect_ok(run([rtuscope, "export", native, "-o", again], True),
                                     "export of a raw export on a terminal")
        check_shown(err_export, ["exporting"], passes=1)
        os.remove(native)
        os.remove(again)
    elif check == "error":
        # The damaged line is at the end: the report fails there (exit 2) with the line erased
        # before the message, which starts on a clean line.
        cmd = [rtuscope, "report", big, "--no-identify"]
        code, out_tty, err_tty = run(cmd, True)
        if code != 2:
            fail(f"damaged capture: exit {code}, expected 2: {err_tty[-300:]!r}")
        drawn = progress_lines(err_tty)
        if not any(label == b"decoding 2/2" for label, *_ in drawn):
            fail(f"no progress before the error: {err_tty[:300]!r}")
        tail = err_tty[err_tty.rindex(ERASE) + len(ERASE):]
        if not re.fullmatch(rb"rtuscope: [^\r\x1b]*big\.hex:\d+:\d+: [^\r\x1b]*\n", tail):
            fail(f"error message not alone on a cleared line: {tail!r}")
        code_q, out_q, err_q = run(cmd + ["--quiet"], True)
        check_absent(err_q, "--quiet")
        if code_q != code or out_q != out_tty or err_q != tail:
            fail(f"--quiet run differs: exit {code_q}, stderr {err_q!r}")
    else:
        fail(f"unknown check {check}")
    os.remove(big)
    print(f"ok: progress {check}")


if __name__ == "__main__":
    main()
