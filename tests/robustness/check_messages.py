#!/usr/bin/env python3
"""Errors say where: `check-map` given a folder, and an unknown model in a --bus file.

- `check-map DIR` checks the folder's *.toml maps (the bundled folder: every map ok); a
  folder with none is reported as "is a directory", not as a map missing its tables.
- A bus file naming a model no map has is reported at its file and line.
- A capture without a byte (an empty file, a header of comments, a pcapng of headers only)
  decodes to nothing with a warning that says so; its timing note claims no observation and
  its report no clean bill of health.
"""
import argparse
import json
import os
import subprocess
import sys

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail, fresh_dir  # noqa: E402  (after the path line)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--work", required=True)
    args = ap.parse_args()
    fresh_dir(args.work)

    maps = os.path.join(args.source, "dissectors")
    run = subprocess.run([args.rtuscope, "check-map", maps], capture_output=True, text=True)
    expected = sorted(f for f in os.listdir(maps) if f.endswith(".toml"))
    checked = sorted(os.path.basename(line.split(":")[0]) for line in run.stdout.splitlines()
                     if ": ok: model " in line)
    if run.returncode != 0 or checked != expected:
        fail(f"check-map {maps}: exit {run.returncode}, checked {checked}, expected {expected}")

    empty = os.path.join(args.work, "no-maps")
    os.makedirs(empty)
    run = subprocess.run([args.rtuscope, "check-map", empty], capture_output=True, text=True)
    if run.returncode != 2 or f"{empty}: is a directory" not in run.stderr:
        fail(f"check-map on a folder without maps: exit {run.returncode}: {run.stderr}")
    print(f"check-map DIR: {len(checked)} maps checked; a folder without maps is named as one")

    bus = os.path.join(args.work, "plant.toml")
    with open(bus, "w") as f:
        f.write('[line]\nbaud = 9600\n\n[slaves]\n1 = "yw2050"\n2 = "nosuchmodel"\n')
    capture = os.path.join(args.source, "captures", "bus_9600_usb.hex")
    run = subprocess.run([args.rtuscope, "decode", "--bus", bus, capture], capture_output=True,
                         text=True)
    if run.returncode != 2 or f"{bus}:6: slave 2: no device map for model 'nosuchmodel'" \
            not in run.stderr:
        fail(f"unknown model in a bus file: exit {run.returncode}: {run.stderr}")
    print("unknown model in a bus file: reported at its file and line")

    check_empty_captures(args.rtuscope, args.work)


def check_empty_captures(rtuscope, work):
    empty = os.path.join(work, "empty.hex")
    open(empty, "w").close()
    comments = os.path.join(work, "comments.hex")
    with open(comments, "w") as f:
        f.write("# baud=19200 parity=E stop=1\n# nothing was heard\n")
    headers_only = os.path.join(work, "headers-only.pcapng")
    run = subprocess.run([rtuscope, "export", comments, "-o", headers_only, "--raw"],
                         capture_output=True, text=True)
    if run.returncode != 0:
        fail(f"export of a capture without bytes: exit {run.returncode}: {run.stderr}")
    for capture in (empty, comments, headers_only):
        run = subprocess.run([rtuscope, "decode", capture, "--format", "jsonl"],
                             capture_output=True, text=True)
        lines = run.stdout.splitlines()
        if run.returncode != 0 or len(lines) != 1:
            fail(f"decode {capture}: exit {run.returncode}, {len(lines)} lines: {run.stderr}")
        header = json.loads(lines[0])
        warning = "the capture holds no bytes: nothing was decoded"
        if warning not in header["warnings"] or f"{capture}: {warning}" not in run.stderr:
            fail(f"decode {capture}: no warning that it holds no bytes: {header} {run.stderr}")
        if header["per_byte_timing"] or "observable" in header["note"]:
            fail(f"decode {capture}: timing claimed of no bytes: {header}")
        run = subprocess.run([rtuscope, "report", capture], capture_output=True, text=True)
        if run.returncode != 0 or "none: the capture holds no traffic to judge" not in run.stdout \
                or "points to a problem" in run.stdout:
            fail(f"report {capture}: exit {run.returncode}: {run.stdout}")
    print("captures without a byte: decoded to nothing, with a warning and no timing claimed")


if __name__ == "__main__":
    main()
