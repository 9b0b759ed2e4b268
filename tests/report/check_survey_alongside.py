#!/usr/bin/env python3
"""`rtuscope report` of a capture that declares its settings gives the same report whether the
capture is surveyed first or while it is decoded.

A capture that declares its line settings and timing resolution (rtuscope's own recordings and
`export --raw`) is reported in one pass, its survey running alongside the decoding; with --csv
the survey pass comes first as for any capture. For every bundled capture, its raw export is
reported both ways: standard output, standard error and the exit status must be identical.
A two-section file whose second section declares a response timeout the first does not is
decoded again after the survey, and must say that timeout.

A text capture that declares its line settings but not its resolution is reported in one pass
too when its first reads hold one byte each (the resolution is then estimated from a sample):
the bundled text captures are reported both ways as well, and so is a capture whose single-byte
start is followed by batched reads, where the whole capture says otherwise than the sample and
the one-pass decoding must be redone after the survey.
"""
import glob
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail  # noqa: E402  (after the path line)


def run(cmd):
    result = subprocess.run(cmd, capture_output=True, text=True, check=False)
    return result.returncode, result.stdout, result.stderr


def report_both_ways(rtuscope, capture, work, args):
    alongside = run([rtuscope, "report", capture, *args])
    surveyed_first = run([rtuscope, "report", capture, *args, "--csv", os.path.join(work, "p.csv")])
    if alongside != surveyed_first:
        fail(f"report {capture} {' '.join(args)} differs when surveyed first:\n"
             f"alongside: {alongside}\nsurveyed first: {surveyed_first}")
    return alongside


def main():
    rtuscope, source_dir = sys.argv[1], sys.argv[2]
    captures = sorted(p for pattern in ("*.hex", "*.csv", "*.txt")
                      for p in glob.glob(os.path.join(source_dir, "captures", pattern))
                      if ".expected." not in p)
    if len(captures) < 5:
        fail(f"only {len(captures)} bundled captures found")
    compared = 0
    with tempfile.TemporaryDirectory() as work:
        natives = []
        for capture in captures:
            native = os.path.join(work, os.path.basename(capture) + ".pcapng")
            status, _, err = run([rtuscope, "export", capture, "--raw", "-o", native, "-q"])
            if status == 0:
                natives.append(native)
        if len(natives) < 5:
            fail(f"only {len(natives)} raw exports written")
        for native in natives:
            for args in (["--format", "json"], ["--format", "text", "--no-identify"]):
                status, out, _ = report_both_ways(rtuscope, native, work, args)
                if status != 0 or not out:
                    fail(f"report {native} exited {status} with {len(out)} bytes")
                compared += 1
        for capture in captures:
            status, out, _ = report_both_ways(rtuscope, capture, work, ["--format", "json"])
            if status != 0 or not out:
                fail(f"report {capture} exited {status} with {len(out)} bytes")
            compared += 1
        # Single bytes for longer than the sample, then batched reads (the same polls at
        # 9600 baud, 8 and 7 bytes a read): over the whole capture, not mostly single bytes.
        turning = os.path.join(work, "single-then-batched.hex")
        with open(turning, "w", encoding="ascii") as out:
            out.write("# baud=9600 parity=E stop=1\n")
            request, response = "01 03 00 00 00 01 84 0A".split(), "01 03 02 00 2A 39 9B".split()
            t = 0.0
            for poll in range(3000):
                for frame in (request, response):
                    if poll < 1500:
                        for byte in frame:
                            t += 0.00115
                            out.write(f"{t:.6f} {byte}\n")
                    else:
                        t += 0.00115 * len(frame)
                        out.write(f"{t:.6f} {' '.join(frame)}\n")
                    t += 0.01
        status, out, _ = report_both_ways(rtuscope, turning, work, ["--format", "json"])
        if status != 0 or json.loads(out)["capture"]["per_byte_timing"]:
            fail(f"single-then-batched report exited {status} or says per-byte timing")
        compared += 1
        # The timeout comes only with the second section.
        live = os.path.join(source_dir, "captures/regressions/fuzz/pcap/seed-reads-250-live.pcapng")
        joined = os.path.join(work, "two-sections.pcapng")
        with open(joined, "wb") as out:
            for part in (natives[0], live):
                with open(part, "rb") as f:
                    out.write(f.read())
        status, out, _ = report_both_ways(rtuscope, joined, work, ["--format", "json"])
        timeout = json.loads(out)["capture"]["response_timeout_ms"]
        if status != 0 or abs(timeout - 300) > 1e-9:
            fail(f"two-section report exited {status}, response timeout {timeout} ms, expected 300")
        compared += 1
    print(f"{compared} reports identical surveyed alongside and surveyed first")


if __name__ == "__main__":
    main()
