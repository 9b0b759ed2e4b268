#!/usr/bin/env python3
"""Runs the built rtuscope on captures that come through a pipe and checks that it reads
them exactly as the same file given by path.

Each capture (text hex, Saleae CSV, a pcapng written by `rtuscope export --raw`, a pcap
written by `rtuscope export`) is fed to `decode` (text and JSONL), `report --format json`,
`export --raw` and `identify`:
  * by path (the reference);
  * as `-`, standard input being a pipe from another process;
  * as /dev/stdin, the same pipe;
  * as a named FIFO that another process writes;
  * by bash process substitution, <(cat FILE).
Every way gives the same output, byte for byte, but for the name of the input where the
output names it. Then:
  * errors in piped input name the input as typed and say where (line, offset), as for
    the file;
  * an empty pipe, /dev/null, and a FIFO whose writer closes at once are an "empty input"
    error (status 2), not an empty decode;
  * a FIFO nobody writes to yet says, after a moment, that rtuscope waits for it;
  * `-` when standard input is a terminal is refused at once;
  * `-` among other files reads as one capture with them.
Every run has a timeout, so a hang fails the test instead of stopping it.
"""
import json
import os
import pty
import re
import shlex
import subprocess
import sys
import tempfile
import time

TIMEOUT = 30
STDIN_NAME = "standard input"
failures = []


def fail(message):
    failures.append(message)
    print("FAIL:", message)


class Fifo:
    """A named FIFO written by a separate process (cat), removed afterwards."""

    def __init__(self, tmp, source):
        self.path = "capture.fifo"  # relative to `tmp`, where rtuscope runs
        self.where = os.path.join(tmp, self.path)
        if os.path.exists(self.where):
            os.remove(self.where)
        os.mkfifo(self.where)
        self.writer = subprocess.Popen(["sh", "-c", 'exec cat "$1" > "$2"', "sh", source,
                                        self.where])

    def close(self, reader_done):
        if not reader_done:
            self.writer.kill()  # the writer may wait for a reader that is gone
        self.writer.wait()
        os.remove(self.where)


def run_input(rtuscope, mode, command, source, after, tmp):
    """Runs `rtuscope COMMAND INPUT AFTER...` in `tmp` with `source` given the way `mode`
    says. Returns (status, stdout bytes, stderr text, the name the input goes by)."""
    stdin = subprocess.DEVNULL
    writer = None
    fifo = None
    if mode == "path":
        argument, name = source, source
    elif mode in ("stdin", "dev-stdin"):
        writer = subprocess.Popen(["cat", source], stdout=subprocess.PIPE)
        stdin = writer.stdout
        argument, name = ("-", STDIN_NAME) if mode == "stdin" else ("/dev/stdin", "/dev/stdin")
    elif mode == "fifo":
        fifo = Fifo(tmp, source)
        argument, name = fifo.path, fifo.path
    elif mode == "substitution":
        argument, name = None, None
    else:
        raise ValueError(mode)
    if mode == "substitution":
        script = " ".join(shlex.quote(a) for a in [rtuscope, *command])
        script += f" <(cat {shlex.quote(source)}) "
        script += " ".join(shlex.quote(a) for a in after)
        cmd = ["bash", "-c", script]
    else:
        cmd = [rtuscope, *command, argument, *after]
    finished = False
    try:
        result = subprocess.run(cmd, stdin=stdin, capture_output=True, timeout=TIMEOUT,
                                check=False, cwd=tmp)
        finished = True
    except subprocess.TimeoutExpired:
        return None, b"", f"still running after {TIMEOUT} s", name or "?"
    finally:
        if writer is not None:
            writer.stdout.close()
            if not finished:
                writer.kill()
            writer.wait()
        if fifo is not None:
            fifo.close(finished)
    stderr = result.stderr.decode(errors="replace")
    if mode == "substitution":
        found = re.search(rb"/dev/fd/\d+|/proc/self/fd/\d+", result.stdout + result.stderr +
                          (exported_bytes(tmp) if "export" in command else b""))
        name = found.group(0).decode() if found else "/dev/fd/"
    return result.returncode, result.stdout, stderr, name


def normalised(data, name):
    """The output with the input's name replaced, so that only what was read compares."""
    if isinstance(data, bytes):
        return data.replace(name.encode(), b"<input>")
    return data.replace(name, "<input>")


def run(cmd, expect=0, **kwargs):
    result = subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT, check=False,
                            **kwargs)
    if result.returncode != expect:
        fail(f"{' '.join(cmd)} exited {result.returncode} (expected {expect}): {result.stderr}")
    return result


MODES = ("stdin", "dev-stdin", "fifo", "substitution")
EXPORTED = "out.pcapng"


def exported_bytes(tmp):
    with open(os.path.join(tmp, EXPORTED), "rb") as f:
        return f.read()


def same_export_as_file(rtuscope, tmp, source, name):
    """What `export --raw` writes for `source` as a file whose name is as long as `name`,
    with that name then put in: a pcapng names its source, and names of one length give
    the same layout, so this is what the export must be, byte for byte."""
    stand_in = "Q" * len(name)
    with open(source, "rb") as f, open(os.path.join(tmp, stand_in), "wb") as out:
        out.write(f.read())
    status, _, stderr, _ = run_input(rtuscope, "path", ["export"], stand_in,
                                     ["-o", EXPORTED, "--raw"], tmp)
    if status != 0:
        fail(f"export of {stand_in} exited {status}: {stderr}")
    return exported_bytes(tmp).replace(stand_in.encode(), name.encode())


def check_same_output(rtuscope, tmp, label, source):
    """Every command, every way of piping: the same output as by path."""
    commands = (
        ("decode", ["decode"], []),
        ("decode jsonl", ["decode"], ["--format", "jsonl"]),
        ("report json", ["report"], ["--format", "json"]),
        ("export --raw", ["export"], ["-o", EXPORTED, "--raw"]),
        ("identify", ["identify"], []),
    )
    for what, command, after in commands:
        reference = run_input(rtuscope, "path", command, source, after, tmp)
        exported = exported_bytes(tmp) if what.startswith("export") else b""
        if reference[0] != 0:
            fail(f"{label}: {what} of the file exited {reference[0]}: {reference[2]}")
            continue
        if not reference[1] and not exported:
            fail(f"{label}: {what} of the file wrote nothing")
        for mode in MODES:
            status, stdout, stderr, name = run_input(rtuscope, mode, command, source, after, tmp)
            where = f"{label}: {what} via {mode}"
            if status != 0:
                fail(f"{where}: exited {status}: {stderr.strip()}")
                continue
            if normalised(stdout, name) != normalised(reference[1], source):
                fail(f"{where}: output differs from the file's")
            if normalised(stderr, name) != normalised(reference[2], source):
                fail(f"{where}: messages differ from the file's: {stderr!r} / {reference[2]!r}")
            if what.startswith("export"):
                piped = exported_bytes(tmp)
                if piped != same_export_as_file(rtuscope, tmp, source, name):
                    fail(f"{where}: the exported file differs from the file's")
            if "/tmp" in stderr.replace(tmp, "") or "rtuscope-input" in stderr:
                fail(f"{where}: a message names the temporary copy: {stderr!r}")


def check_errors_name_the_input(rtuscope, tmp, label, source):
    """A damaged capture: the same error, status and position as from the file."""
    reference = run_input(rtuscope, "path", ["decode"], source, [], tmp)
    if reference[0] != 2:
        fail(f"{label}: the damaged file exited {reference[0]}, expected 2: {reference[2]}")
        return
    for mode in MODES:
        status, _, stderr, name = run_input(rtuscope, mode, ["decode"], source, [], tmp)
        where = f"{label} via {mode}"
        if status != 2:
            fail(f"{where}: exited {status}, expected 2: {stderr!r}")
        elif normalised(stderr, name) != normalised(reference[2], source):
            fail(f"{where}: error {stderr!r} differs from the file's {reference[2]!r}")
        elif f"{name}:" not in stderr:
            fail(f"{where}: the error does not name the input {name!r}: {stderr!r}")


def write(tmp, name, data):
    path = os.path.join(tmp, name)
    with open(path, "wb") as f:
        f.write(data)
    return path


def check_empty_inputs(rtuscope, tmp):
    def expect_empty(where, status, stderr, name):
        if status != 2 or "empty input" not in stderr or name not in stderr:
            fail(f"{where}: expected status 2 and '{name}: ... empty input', got {status}: "
                 f"{stderr!r}")

    empty_pipe = subprocess.Popen(["true"], stdout=subprocess.PIPE)
    result = subprocess.run([rtuscope, "decode", "-"], stdin=empty_pipe.stdout,
                            capture_output=True, text=True, timeout=TIMEOUT, check=False)
    empty_pipe.stdout.close()
    empty_pipe.wait()
    expect_empty("an empty pipe", result.returncode, result.stderr, STDIN_NAME)
    if result.stdout:
        fail(f"an empty pipe: wrote output anyway: {result.stdout!r}")

    with open(os.devnull, "rb") as null:
        result = subprocess.run([rtuscope, "report", "-"], stdin=null, capture_output=True,
                                text=True, timeout=TIMEOUT, check=False)
    expect_empty("/dev/null as -", result.returncode, result.stderr, STDIN_NAME)

    empty = write(tmp, "empty.hex", b"")
    status, _, stderr, name = run_input(rtuscope, "fifo", ["decode"], empty, [], tmp)
    expect_empty("a FIFO whose writer closes at once", status, stderr, name)
    status, _, stderr, name = run_input(rtuscope, "substitution", ["decode"], empty, [], tmp)
    expect_empty("an empty process substitution", status, stderr, name)


def check_silent_fifo(rtuscope, tmp):
    """Nobody writes yet: rtuscope says what it waits for, and ends when the writer closes."""
    fifo = os.path.join(tmp, "silent.fifo")
    os.mkfifo(fifo)
    started = time.monotonic()
    proc = subprocess.Popen([rtuscope, "decode", fifo], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    time.sleep(4)
    # Opening for writing without blocking proves that rtuscope holds the FIFO open.
    try:
        writer = os.open(fifo, os.O_WRONLY | os.O_NONBLOCK)
    except OSError as e:
        proc.kill()
        proc.communicate()
        fail(f"a silent FIFO: rtuscope has not opened it after 4 s: {e}")
        return
    os.close(writer)
    try:
        _, stderr = proc.communicate(timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        fail("a silent FIFO: rtuscope still runs after its writer closed")
        return
    if f"waiting for {fifo}" not in stderr:
        fail(f"a silent FIFO: no word on what rtuscope waits for: {stderr!r}")
    if proc.returncode != 2 or "empty input" not in stderr:
        fail(f"a silent FIFO closed: expected an empty input error, got {proc.returncode}: "
             f"{stderr!r}")
    if time.monotonic() - started > TIMEOUT:
        fail("a silent FIFO: took too long")


def check_terminal_refused(rtuscope):
    controller, terminal = pty.openpty()
    try:
        result = subprocess.run([rtuscope, "decode", "-"], stdin=terminal, capture_output=True,
                                text=True, timeout=TIMEOUT, check=False)
    except subprocess.TimeoutExpired:
        fail("- on a terminal: rtuscope waits for typed input instead of refusing")
        return
    finally:
        os.close(terminal)
        os.close(controller)
    if result.returncode != 2 or "terminal" not in result.stderr:
        fail(f"- on a terminal: expected a refusal (status 2), got {result.returncode}: "
             f"{result.stderr!r}")


def check_stdin_in_a_set(rtuscope, tmp, capture):
    """`-` among other files: the set reads in time order as the whole capture."""
    with open(capture, "rb") as f:
        lines = f.read().splitlines(keepends=True)
    header = [line for line in lines if line.startswith(b"#")]
    body = [line for line in lines if not line.startswith(b"#")]
    half = len(body) // 2
    first = write(tmp, "first-half.hex", b"".join(header + body[:half]))
    second = write(tmp, "second-half.hex", b"".join(header + body[half:]))
    whole = [json.loads(line) for line in
             run([rtuscope, "decode", capture, "--format", "jsonl"]).stdout.splitlines()][1:]
    with open(first, "rb") as stdin:
        result = run([rtuscope, "decode", second, "-", "--format", "jsonl"], stdin=stdin)
    records = [json.loads(line) for line in result.stdout.splitlines()]
    if not records:
        return
    if records[0].get("source") != f"{STDIN_NAME} \u2026 {second} (2 files)":
        fail(f"- in a set: the source is {records[0].get('source')!r}")
    if records[1:] != whole:
        fail("- in a set: the records differ from the whole capture's")
    for twice in (["-", "-"], ["-", "/dev/stdin"]):
        writer = subprocess.Popen(["cat", first], stdout=subprocess.PIPE)
        result = run([rtuscope, "decode", *twice, "--format", "jsonl"], stdin=writer.stdout,
                     expect=0 if twice == ["-", "-"] else 2)
        writer.stdout.close()
        writer.wait()
        if twice != ["-", "-"] and "once" not in result.stderr:
            fail(f"{' '.join(twice)}: expected a refusal to read standard input twice: "
                 f"{result.stderr!r}")


def main():
    rtuscope, captures = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    hex_capture = os.path.join(captures, "bus_9600_usb.hex")
    with tempfile.TemporaryDirectory(prefix="rtuscope-pipe-") as tmp:
        pcapng = os.path.join(tmp, "raw.pcapng")
        run([rtuscope, "export", hex_capture, "-o", pcapng, "--raw"])
        pcap = os.path.join(tmp, "frames.pcap")
        run([rtuscope, "export", hex_capture, "-o", pcap])
        inputs = (
            ("text hex", hex_capture),
            ("Saleae CSV", os.path.join(captures, "device_examples_saleae_table.csv")),
            ("pcapng", pcapng),
            ("pcap", pcap),
        )
        for label, source in inputs:
            check_same_output(rtuscope, tmp, label, source)

        with open(hex_capture, "rb") as f:
            text = f.read()
        check_errors_name_the_input(
            rtuscope, tmp, "a bad text line",
            write(tmp, "bad.hex", text[:2000].rsplit(b"\n", 1)[0] + b"\n0.5 01 zz\n"))
        with open(inputs[1][1], "rb") as f:
            csv = f.read()
        check_errors_name_the_input(
            rtuscope, tmp, "a bad Saleae row",
            write(tmp, "bad.csv", csv[:1000].rsplit(b"\n", 1)[0] + b"\nnot,a,row\n"))
        with open(pcapng, "rb") as f:
            check_errors_name_the_input(rtuscope, tmp, "a pcapng cut short",
                                        write(tmp, "cut.pcapng", f.read()[:-7]))
        check_errors_name_the_input(rtuscope, tmp, "a gzip-compressed capture",
                                    write(tmp, "packed.hex",
                                          subprocess.run(["gzip", "-c", hex_capture],
                                                         capture_output=True,
                                                         check=True).stdout))
        check_empty_inputs(rtuscope, tmp)
        check_silent_fifo(rtuscope, tmp)
        check_terminal_refused(rtuscope)
        check_stdin_in_a_set(rtuscope, tmp, hex_capture)
    if failures:
        print(f"{len(failures)} failures")
        sys.exit(1)
    print("ok: captures read from pipes, FIFOs and process substitution as from files")


if __name__ == "__main__":
    main()
