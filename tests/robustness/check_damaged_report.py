#!/usr/bin/env python3
"""A report of a damaged capture covers every record that could be read.

A recording cut inside a block (a copy taken while it was written, a power loss), or a text
capture with a line that is not one, stops the read of that file at the damage; in a set of
files, the files after a damaged one are read on. `decode` writes every record that could
be read; `report` must likewise write its report of those records, say in it where the
capture was damaged, and still fail with exit 2 and the reader's message. Checked on:
- a live-style recording (`export --raw`: declared settings, so the report reads it once),
  cut inside an enhanced packet block;
- the same as the second file of a rotation set after a whole one;
- the same as the middle file of a set of three: the third is read too;
- a text hex capture with a bad line in the middle (its survey pass reads to the damage).
In each case the report counts exactly the frames `decode` wrote, and fewer than the whole
capture holds.
"""
import argparse
import json
import os
import struct
import subprocess
import sys

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail, fresh_dir  # noqa: E402  (after the path line)

WARNING = "the capture is damaged: "


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True)


def decoded_frames(rtuscope, files):
    """Frames `decode` writes, and its exit code and error output."""
    r = run([rtuscope, "decode", *files, "--format", "jsonl", "-q"])
    frames = sum(1 for line in r.stdout.splitlines() if json.loads(line)["kind"] == "frame")
    return frames, r.returncode, r.stderr


def reported(rtuscope, files):
    r = run([rtuscope, "report", *files, "--format", "json", "-q"])
    try:
        report = json.loads(r.stdout)
    except json.JSONDecodeError:
        fail(f"report {files}: exit {r.returncode}, no JSON report on stdout: {r.stderr}")
    return report, r.returncode, r.stderr


def cut_inside_a_block(path, out):
    """Copies the pcapng at `path` to `out`, cut in the middle of the enhanced packet block
    that holds its middle byte; returns the offset of that block."""
    data = open(path, "rb").read()
    at = 0
    while at < len(data):
        kind, length = struct.unpack_from("<II", data, at)
        if kind == 6 and at + length > len(data) // 2:
            with open(out, "wb") as f:
                f.write(data[:at + length // 2])
            return at
        at += length
    fail(f"{path}: no enhanced packet block past its middle")


def check_damaged(rtuscope, files, whole_frames, where, at_least=0):
    """The report of `files`, damaged at `where`, against decode of the same; the report
    counts more than `at_least` frames."""
    frames, decode_rc, decode_err = decoded_frames(rtuscope, files)
    if decode_rc != 2 or where not in decode_err:
        fail(f"decode {files}: exit {decode_rc}, expected 2 naming {where!r}: {decode_err}")
    report, rc, err = reported(rtuscope, files)
    if rc != 2 or where not in err or "the report covers every record that could be read" \
            not in err:
        fail(f"report {files}: exit {rc}, expected 2 naming {where!r}: {err}")
    warnings = [w for w in report["capture"]["warnings"] if w.startswith(WARNING)]
    if len(warnings) != 1 or where not in warnings[0]:
        fail(f"report {files}: no warning naming {where!r}: {report['capture']['warnings']}")
    counted = report["totals"]["frames"]
    if counted != frames or not at_least < counted < whole_frames:
        fail(f"report {files}: {counted} frames, decode wrote {frames}, the whole capture "
             f"holds {whole_frames}, expected more than {at_least}")
    print(f"{' '.join(os.path.basename(f) for f in files)}: report of the {counted} frames "
          f"that could be read ({whole_frames} in the whole), exit 2, warning: {warnings[0]}")


def days_later(args, days):
    """The capture's traffic `days` later, as a live-style recording; returns its path."""
    shifted = os.path.join(args.work, f"later{days}.hex")
    with open(args.capture) as src, open(shifted, "w") as dst:
        for line in src:
            stamp, sep, rest = line.partition(" ")
            if line.startswith("#") or not sep:
                dst.write(line)
            else:
                whole_s, dot, fraction = stamp.partition(".")
                dst.write(f"{int(whole_s) + 86400 * days}{dot}{fraction}{sep}{rest}")
    recording = os.path.join(args.work, f"later{days}.pcapng")
    r = run([args.rtuscope, "export", shifted, "--raw", "-o", recording])
    if r.returncode != 0:
        fail(f"export --raw of the shifted capture: exit {r.returncode}: {r.stderr}")
    return recording


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--capture", required=True, help="a text hex capture")
    ap.add_argument("--work", required=True)
    args = ap.parse_args()
    fresh_dir(args.work)

    recording = os.path.join(args.work, "recording.pcapng")
    r = run([args.rtuscope, "export", args.capture, "--raw", "-o", recording])
    if r.returncode != 0:
        fail(f"export --raw: exit {r.returncode}: {r.stderr}")
    whole, rc, err = reported(args.rtuscope, [recording])
    if rc != 0 or any(w.startswith(WARNING) for w in whole["capture"]["warnings"]):
        fail(f"report of the whole recording: exit {rc}: {err} {whole['capture']['warnings']}")
    whole_frames = whole["totals"]["frames"]

    cut = os.path.join(args.work, "cut.pcapng")
    block = cut_inside_a_block(recording, cut)
    where = f"cut.pcapng: offset {block}: "
    check_damaged(args.rtuscope, [cut], whole_frames, where)

    # A rotation set whose second file is the cut one: the first is read whole.
    first = os.path.join(args.work, "set-0001.pcapng")
    second = os.path.join(args.work, "set-0002.pcapng")
    r = run([args.rtuscope, "export", args.capture, "--raw", "-o", first])
    if r.returncode != 0:
        fail(f"export --raw: exit {r.returncode}: {r.stderr}")
    # The second file: the same traffic a day later (the set is read in time order).
    later = days_later(args, 1)
    block = cut_inside_a_block(later, second)
    check_damaged(args.rtuscope, [first, second], 2 * whole_frames,
                  f"set-0002.pcapng: offset {block}: ")
    # The cut file between two whole ones: the third is read after it, across a break.
    third = days_later(args, 2)
    where = f"set-0002.pcapng: offset {block}: "
    check_damaged(args.rtuscope, [first, second, third], 3 * whole_frames, where,
                  at_least=2 * whole_frames)

    # A text capture with a line that is not one, in its middle.
    lines = open(args.capture).read().splitlines(keepends=True)
    middle = len(lines) // 2
    bad = os.path.join(args.work, "bad.hex")
    with open(bad, "w") as f:
        f.writelines(lines[:middle])
        f.write("12.5 zz 01\n")
        f.writelines(lines[middle:])
    text_whole, rc, err = reported(args.rtuscope, [args.capture])
    if rc != 0:
        fail(f"report {args.capture}: exit {rc}: {err}")
    check_damaged(args.rtuscope, [bad], text_whole["totals"]["frames"],
                  f"bad.hex:{middle + 1}:6: expected hex byte pair, found 'zz'")


if __name__ == "__main__":
    main()
