#!/usr/bin/env python3
"""`rtuscope report` spreads its stages over threads that share the usable cores, and the
scheduling differs with their number (a parsing thread yields its priority where the threads
outnumber the cores). The report must not: every bundled capture, its raw export (a live
recording's format) and a simulated heavy USB recording are reported on all the cores and
under `taskset -c 0`, and standard output, standard error and the exit status must be
identical.

  check_one_core.py RTUSCOPE RTUSIM SOURCE_DIR
"""
import glob
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail  # noqa: E402  (after the path line)


def run(cmd):
    result = subprocess.run(cmd, capture_output=True, text=True, check=False)
    return result.returncode, result.stdout, result.stderr


def main():
    rtuscope, rtusim, source = sys.argv[1:4]
    if shutil.which("taskset") is None:
        fail("taskset is not installed (util-linux)")
    if len(os.sched_getaffinity(0)) < 2:
        print("one usable core: nothing to compare it with (skipped)")
        sys.exit(77)
    with tempfile.TemporaryDirectory() as work:
        captures = sorted(glob.glob(os.path.join(source, "captures", "*.hex")))
        for capture in list(captures):
            raw = os.path.join(work, os.path.basename(capture) + ".pcapng")
            code, _, err = run([rtuscope, "export", capture, "--raw", "-o", raw, "-q"])
            if code != 0:
                fail(f"export --raw {capture}: {err}")
            captures.append(raw)
        recording = os.path.join(work, "usb.pcapng")
        subprocess.run([rtusim, "--transactions", "20000", "--baud", "19200", "--chunking",
                        "usb", "--profile", "heavy", "--seed", "4", "--pcapng", recording],
                       check=True)
        captures.append(recording)
        for capture in captures:
            for args in (["--format", "json"], ["--format", "text"]):
                everywhere = run([rtuscope, "report", capture, *args])
                one_core = run(["taskset", "-c", "0", rtuscope, "report", capture, *args])
                if everywhere != one_core:
                    fail(f"report {capture} {' '.join(args)} differs on one core:\n"
                         f"all cores: {everywhere}\none core: {one_core}")
                if everywhere[0] != 0 or not everywhere[1]:
                    fail(f"report {capture} {' '.join(args)} failed: {everywhere[2]}")
        print(f"{len(captures)} captures: the same report on one core as on all")


if __name__ == "__main__":
    main()
