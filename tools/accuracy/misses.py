#!/usr/bin/env python3
"""Sorts the truth frames a decoder missed (see score.py: recall) into classes, with examples.

For each missed truth frame it looks at the decoded records that share a byte with it and at
the truth records those also cover:

  damaged+noise     a damaged frame (fault crc or truncated) decoded together with noise
                    next to it (a burst, a turnaround or glitch byte)
  damaged+frame     a damaged frame decoded together with (part of) another frame
  damaged split     a damaged frame cut into pieces, none of them reaching past it
  runaway record    an intact frame inside a decoded record that covers three or more
                    truth frames (the decoder lost its footing for a while)
  next to damage    an intact frame decoded together with (part of) a damaged frame next to
                    it: "after" when the damaged one comes first (the clean frame after damage)
  glitch absorbed   an intact frame decoded together with a glitch byte
  noise absorbed    an intact frame decoded together with burst or turnaround noise
  glued frames      an intact frame decoded together with another intact frame
  split             an intact frame cut into pieces, none of them reaching past it
  as noise          an intact frame decoded as one noise record with exactly its bytes
  other             anything else

Where a miss joins the frame to a neighbour, the silence between the two on the wire is
noted: at t1.5 or more, per-byte timestamps show that boundary (a frame cannot span it
without a t1.5 fault), so timing alone could have placed it.

Each example shows the missed frame with its neighbours in the truth (bytes, cause or
faults, the silence between them in ms and in t3.5 units) and the decoded records around it.

  misses.py TRUTH DECODED [--examples N]
  misses.py --manifest FILE [--examples N]     rows as for score.py; counts per label
Python 3 standard library only.
"""
import argparse
import collections
import json
import os
import sys

import score

DAMAGE = score.DAMAGE
CLASSES = ("damaged+noise", "damaged+frame", "damaged split", "runaway record",
           "next to damage (after)", "next to damage (before)", "glitch absorbed",
           "noise absorbed", "glued frames", "split", "as noise", "other")


def end(r):
    return r["_pos"] + len(r["_hex"]) // 2


def overlapping(records, lo, hi):
    return [r for r in records if r["_pos"] < hi and end(r) > lo]


def damaged(r):
    return r["kind"] == "frame" and bool(DAMAGE & set(r.get("faults", [])))


def classify(frame, truth, decoded):
    """(class, silence in s between the frame and a neighbour wrongly joined to it, or None)."""
    lo, hi = frame["_pos"], end(frame)
    near = overlapping(decoded, lo, hi)
    if len(near) == 1 and near[0]["kind"] == "noise" and near[0]["_hex"] == frame["_hex"]:
        return "as noise", None
    span_lo = min(r["_pos"] for r in near)
    span_hi = max(end(r) for r in near)
    others = [t for t in overlapping(truth, span_lo, span_hi) if t is not frame]
    k = next(i for i, r in enumerate(truth) if r is frame)
    joined = []
    if k > 0 and truth[k - 1] in others:
        joined.append(frame["t"] - truth[k - 1]["t_end"])
    if k + 1 < len(truth) and truth[k + 1] in others:
        joined.append(truth[k + 1]["t"] - frame["t_end"])
    gap = max(joined) if joined else None
    if damaged(frame):
        if any(t["kind"] == "noise" for t in others):
            return "damaged+noise", gap
        if others:
            return "damaged+frame", gap
        return "damaged split", gap
    widest = max(sum(1 for t in overlapping(truth, d["_pos"], end(d)) if t["kind"] == "frame")
                 for d in near)
    if widest >= 3:
        return "runaway record", gap
    hurt = [t for t in others if damaged(t)]
    if hurt:
        side = "after" if hurt[0]["_pos"] < lo else "before"
        return f"next to damage ({side})", gap
    if any(t["kind"] == "noise" and t.get("cause") == "glitch" for t in others):
        return "glitch absorbed", gap
    if any(t["kind"] == "noise" for t in others):
        return "noise absorbed", gap
    if others:
        return "glued frames", gap
    if len(near) > 1:
        return "split", gap
    return "other", gap


def describe(frame, truth, decoded, t3_5):
    """Lines showing the frame, its truth neighbours and the decoded records around it."""
    k = next(i for i, r in enumerate(truth) if r is frame)
    lines = []
    prev_end = None
    for r in truth[max(0, k - 2):k + 3]:
        gap = ""
        if prev_end is not None:
            g = r["t"] - prev_end
            gap = f"  +{g * 1e3:.3f} ms ({g / t3_5:.2f} t3.5)"
        prev_end = r["t_end"]
        what = (",".join(r.get("faults", [])) or "intact") if r["kind"] == "frame" \
            else r.get("cause", "")
        mark = ">>" if r is frame else "  "
        extra = f" flipped {r['flipped']}" if r.get("flipped") else ""
        extra += f" of {r['intended_size']}" if r.get("intended_size") else ""
        lines.append(f"    {mark} truth   {r['kind']:5} {r['_hex']} [{what}{extra}]{gap}")
    lo, hi = frame["_pos"], end(frame)
    for d in overlapping(decoded, lo - 16, hi + 16):
        issues = ",".join(d.get("issues", [])) if isinstance(d.get("issues"), list) else ""
        inside = "*" if d["_pos"] < hi and end(d) > lo else " "
        lines.append(f"     {inside} decoded {d['kind']:5} {d['_hex']} {issues}")
    return lines


def analyse(truth_path, decoded_path):
    truth = score.load(truth_path)
    decoded = score.load(decoded_path)
    t1_5, t3_5 = score.line_times(truth_path)
    s = score.score(truth, decoded, t3_5)
    out = []
    for frame in s["_misses"]:
        cls, gap = classify(frame, truth, decoded)
        visible = gap is not None and gap >= t1_5
        out.append((cls, visible, frame, gap, describe(frame, truth, decoded, t3_5)))
    return s, out


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("truth", nargs="?")
    ap.add_argument("decoded", nargs="?")
    ap.add_argument("--manifest")
    ap.add_argument("--examples", type=int, default=3, metavar="N",
                    help="examples per class (0: counts only)")
    args = ap.parse_args(argv)
    if args.manifest:
        with open(args.manifest, encoding="utf-8") as f:
            runs = [line.rstrip("\n").split("\t") for line in f if line.strip()]
        runs = [(label, truth, dec) for label, _, truth, dec in runs]
    elif args.truth and args.decoded:
        runs = [("run", args.truth, args.decoded)]
    else:
        ap.error("give TRUTH and DECODED, or --manifest")
    counts = collections.OrderedDict()
    visible = collections.Counter()
    examples = collections.defaultdict(list)
    for label, truth_path, decoded_path in runs:
        _, misses = analyse(truth_path, decoded_path)
        c = counts.setdefault(label, collections.Counter())
        for cls, seen, frame, gap, lines in misses:
            c[cls] += 1
            visible[cls] += seen
            examples[cls].append((label, os.path.basename(truth_path), frame, gap, lines))
    used = [c for c in CLASSES if any(counts[label][c] for label in counts)]
    print("missed frames by class (misses.py):")
    header = ["configuration", "missed"] + used
    rows = [[label, str(sum(c.values()))] + [str(c[k]) for k in used] for label, c in
            counts.items()]
    rows.append(["of which joined across >= t1.5", str(sum(visible.values()))]
                + [str(visible[k]) for k in used])
    widths = [max(len(r[i]) for r in [header] + rows) for i in range(len(header))]
    for r in [header] + rows:
        print("  ".join(x.ljust(w) if i == 0 else x.rjust(w) for i, (x, w) in
                        enumerate(zip(r, widths))))
    if args.examples:
        for cls in used:
            print(f"\n{cls}: {len(examples[cls])}")
            # Spread the examples over the runs rather than taking the first run's.
            picked = examples[cls][::max(1, len(examples[cls]) // args.examples)][:args.examples]
            for label, name, frame, gap, lines in picked:
                joined = "" if gap is None else f", joined across {gap * 1e3:.3f} ms of silence"
                print(f"  {label} ({name}) stream byte {frame['_pos']}, "
                      f"t={frame['t']:.6f} s{joined}")
                print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
