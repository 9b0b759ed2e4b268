#!/usr/bin/env python3
"""`export` on captures that pcap cannot hold as they are, and on damaged ones.

- A valid text capture whose first frame starts before t = 0 once its transmission time is
  counted back: exported with every time shifted by whole seconds, said on stderr, and read by
  tshark with the same gaps.
- A capture damaged after its first frame: exit 2 with file and line, and no output file, not
  even a partial one; an older file of the same name is left as it was.
- An output that is a FIFO (as /dev/null, a device) is written into, not replaced by a file:
  a reader on the other end gets the whole pcapng, which tshark reads.
"""
import argparse
import os
import stat
import subprocess
import sys

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail, fresh_dir  # noqa: E402  (after the path line)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--tshark", required=True)
    ap.add_argument("--work", required=True)
    args = ap.parse_args()
    fresh_dir(args.work)

    early = os.path.join(args.work, "early.hex")
    with open(early, "w") as f:
        f.write("# baud=9600 parity=E stop=1\n"
                "0.005 01 03 00 00 00 20 44 12\n"
                "0.100 01 03 06 5a 02 5d 2b b6 db 0f 18\n")
    out = os.path.join(args.work, "early.pcapng")
    run = subprocess.run([args.rtuscope, "export", early, "-o", out], capture_output=True,
                         text=True, timeout=60)
    if run.returncode != 0 or "every time is 1 s later" not in run.stderr:
        fail(f"export of a capture starting before 0: exit {run.returncode}: {run.stderr}")
    times = subprocess.run([args.tshark, "-r", out, "-T", "fields", "-e", "frame.time_epoch"],
                           capture_output=True, text=True, timeout=60).stdout.split()
    # 8 bytes at 9600 8E1 take 9.166664 ms: the request started 4.166664 ms before 0.
    if [round(float(t), 6) for t in times] != [0.995833, 1.087396]:
        fail(f"shifted times read by tshark: {times}")
    print(f"starts before 0: exported 1 s later, tshark reads {times}")

    damaged = os.path.join(args.work, "damaged.hex")
    with open(damaged, "w") as f:
        f.write("# baud=9600 parity=E stop=1\n1.005 01 03 00 00 00 20 44 12\nzz\n")
    out = os.path.join(args.work, "damaged.pcapng")
    with open(out, "w") as f:
        f.write("an older file")
    run = subprocess.run([args.rtuscope, "export", damaged, "-o", out], capture_output=True,
                         text=True, timeout=60)
    if run.returncode != 2 or f"{damaged}:3:" not in run.stderr:
        fail(f"damaged capture: exit {run.returncode}, expected 2 with file:line: {run.stderr}")
    if open(out).read() != "an older file" or os.path.exists(out + ".partial"):
        fail("a failed export left a partial file or changed the older one")
    print("damaged: exit 2 with file:line, no partial output, the older file untouched")

    fifo = os.path.join(args.work, "to_reader.pcapng")
    os.mkfifo(fifo)
    copy = os.path.join(args.work, "read_from_fifo.pcapng")
    with open(copy, "wb") as sink:
        reader = subprocess.Popen(["cat", fifo], stdout=sink)
        try:
            run = subprocess.run([args.rtuscope, "export", early, "-o", fifo, "-q"],
                                 capture_output=True, text=True, timeout=60)
            reader.wait(timeout=30)
        except subprocess.TimeoutExpired:
            reader.kill()
            fail("export into a FIFO: the reader never got an end (the FIFO was not written)")
    if run.returncode != 0:
        fail(f"export into a FIFO: exit {run.returncode}: {run.stderr}")
    if not stat.S_ISFIFO(os.stat(fifo).st_mode) or os.path.exists(fifo + ".partial"):
        fail("export into a FIFO replaced it with a file or left a partial one")
    frames = subprocess.run([args.tshark, "-r", copy, "-T", "fields", "-e", "frame.number"],
                            capture_output=True, text=True, timeout=60).stdout.split()
    if frames != ["1", "2"]:
        fail(f"the pcapng read from the FIFO: tshark found frames {frames}")
    print("FIFO: written into, still a FIFO, its reader got 2 frames")


if __name__ == "__main__":
    main()
