#!/usr/bin/env python3
"""Errors say where: `check-map` given a folder, and an unknown model in a --bus file.

- `check-map DIR` checks the folder's *.toml maps (the bundled folder: every map ok); a
  folder with none is reported as "is a directory", not as a map missing its tables.
- A bus file naming a model no map has is reported at its file and line.
"""
import argparse
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


if __name__ == "__main__":
    main()
