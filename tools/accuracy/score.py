#!/usr/bin/env python3
"""Scores a decoder's JSON-lines output against rtusim's ground truth.

Both files hold one JSON object per record in wire order; records of kind "frame" and
"noise" carry "hex" (every byte of the record). Other kinds (the "capture" header) are
skipped. A record's stream position is the number of bytes in the records before it, so a
record is identified by (position, bytes) whatever its timestamps say.

Metrics
  recall     truth frames found as a decoded record with the same bytes at the same stream
             position. Intact frames must come out as frames; a frame the wire damaged
             (faults "crc" or "truncated") also counts when it comes out as one noise record
             with exactly its bytes, since no decoder can tell such bytes from noise.
  precision  decoded frames that are truth frames (same position, same bytes).
  bytes      the decoded records' bytes, concatenated, equal the wire's: every input byte is
             in exactly one decoded record.
  t error    |decoded t - truth t| of found frames, median and maximum, in ms (reported only:
             with batched reads the decoder can only estimate when a frame started).
  timing     the t1.5 and t3.5 flags on found frames, each true or false by the truth. A t3.5
             flag is true when the line was silent for less than t3.5 before the frame (since
             the end of the record before it, frame or noise); a t1.5 flag is true when the
             truth frame carries the t1.5 fault (a pause inside it). A false flag is timing
             evidence invented where the capture could not show it, and fails the
             configuration; a violation that goes unflagged does not (batched reads hide most
             of them).
  pairing    truth transactions (an intact request and its intact response: no crc,
             truncated or wrong_slave fault) whose two frames share a non-null txn in the
             decoded output; "false pairs" counts decoded txn groups that are not a truth
             request/response pair.

Usage
  score.py TRUTH DECODED [--target 0.999] [--show N]
                                                  one run; exit 1 when below target; --show
                                                  lists missed and false frames
  score.py --manifest FILE                        rows "label<TAB>target<TAB>truth<TAB>decoded";
                                                  rows with one label are summed; prints a table
                                                  and "accuracy: N passed, M failed"
Python 3 standard library only.
"""
import argparse
import json
import os
import sys

# tools/pylib (rtu_timing), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../pylib"))
from rtu_timing import t1_5_seconds, t3_5_seconds  # noqa: E402  (after the path line)

DAMAGE = {"crc", "truncated"}
UNPAIRABLE = {"crc", "truncated", "wrong_slave"}


def load(path):
    """Frame and noise records of a JSON-lines file, each with its stream position."""
    records = []
    pos = 0
    try:
        with open(path, encoding="utf-8") as f:
            for line_no, line in enumerate(f, 1):
                line = line.strip()
                if not line:
                    continue
                try:
                    r = json.loads(line)
                except json.JSONDecodeError as e:
                    raise SystemExit(f"{path}:{line_no}: not JSON: {e}")
                if r.get("kind") not in ("frame", "noise"):
                    continue
                h = r.get("hex", "")
                if not isinstance(h, str) or len(h) % 2:
                    raise SystemExit(f"{path}:{line_no}: expected an even-length hex string")
                r["_pos"] = pos
                r["_hex"] = h.lower()
                pos += len(h) // 2
                records.append(r)
    except FileNotFoundError:
        pass  # a decoder that wrote nothing scores zero
    return records


def line_times(path):
    """t1.5 and t3.5 in seconds from a truth file's capture header."""
    with open(path, encoding="utf-8") as f:
        head = json.loads(f.readline())
    baud, bits = head["baud"], head["bits_per_char"]
    return t1_5_seconds(baud, bits), t3_5_seconds(baud, bits)


# Times in the truth are exact to the nanosecond; a decoder's are rounded to its own output.
TIME_TOLERANCE = 2e-6


def truth_silences(truth):
    """Silence before each truth frame (by id), in seconds: since the end of the record
    before it, frame or noise (any bytes on the line). None for the first record."""
    silences = {}
    prev_end = None
    for r in truth:
        if r["kind"] == "frame":
            silences[id(r)] = None if prev_end is None else float(r["t"]) - prev_end
        prev_end = float(r["t_end"])
    return silences


def score_timing(truth_frames, found, silences, t3_5):
    """Timing flags on found frames against the truth (see the module doc)."""
    counts = {"t35_truth": 0, "t35_flagged": 0, "t35_false": 0,
              "t15_truth": 0, "t15_flagged": 0, "t15_false": 0}
    false_flags = []
    for t in truth_frames:
        silence = silences.get(id(t))
        short_silence = silence is not None and silence < t3_5 - TIME_TOLERANCE
        inner_pause = "t1.5" in t.get("faults", [])
        counts["t35_truth"] += short_silence
        counts["t15_truth"] += inner_pause
        d = found.get(id(t))
        if d is None or d["kind"] != "frame":
            continue
        issues = d.get("issues") or []
        for flag, key, true in (("t3.5", "t35", short_silence), ("t1.5", "t15", inner_pause)):
            if flag in issues:
                counts[key + "_flagged"] += 1
                if not true:
                    counts[key + "_false"] += 1
                    false_flags.append((flag, d, silence))
    return counts, false_flags


def score(truth, decoded, t3_5):
    """Counts for one truth/decoded pair (see the module doc); `t3_5` in seconds."""
    spans = {(r["_pos"], r["_hex"]): r for r in decoded}
    truth_frames = [r for r in truth if r["kind"] == "frame"]
    truth_spans = {(r["_pos"], r["_hex"]): r for r in truth_frames}

    found = {}
    for t in truth_frames:
        d = spans.get((t["_pos"], t["_hex"]))
        if d is None:
            continue
        if d["kind"] == "frame" or DAMAGE & set(t.get("faults", [])):
            found[id(t)] = d

    decoded_frames = [d for d in decoded if d["kind"] == "frame"]
    true_frames = sum(1 for d in decoded_frames if (d["_pos"], d["_hex"]) in truth_spans)

    # Pairing.
    by_txn = {}
    for t in truth_frames:
        if t.get("txn") is not None:
            by_txn.setdefault(t["txn"], []).append(t)
    pairs = 0
    paired = 0
    for group in by_txn.values():
        roles = sorted(g.get("role") for g in group)
        if roles != ["request", "response"]:
            continue
        if any(UNPAIRABLE & set(g.get("faults", [])) for g in group):
            continue
        pairs += 1
        d = [found.get(id(g)) for g in group]
        if all(x is not None and x.get("txn") is not None for x in d) and d[0]["txn"] == d[1]["txn"]:
            paired += 1
    groups = {}
    for d in decoded:
        if d.get("txn") is not None:
            groups.setdefault(d["txn"], []).append(d)
    false_pairs = 0
    for group in groups.values():
        if len(group) < 2:
            continue
        ts = [truth_spans.get((d["_pos"], d["_hex"])) for d in group]
        ok = (len(group) == 2 and all(t is not None for t in ts)
              and ts[0].get("txn") is not None and ts[0].get("txn") == ts[1].get("txn")
              and ts[0].get("role") != ts[1].get("role"))
        if not ok:
            false_pairs += 1

    # How far the decoder's start time of each found frame is from the truth's.
    t_errors = []
    for t in truth_frames:
        d = found.get(id(t))
        if d is not None and isinstance(d.get("t"), (int, float)):
            t_errors.append(abs(float(d["t"]) - float(t["t"])) * 1e3)

    misses = [t for t in truth_frames if id(t) not in found]
    false_frames = [d for d in decoded_frames if (d["_pos"], d["_hex"]) not in truth_spans]

    timing, false_flags = score_timing(truth_frames, found, truth_silences(truth), t3_5)

    truth_stream = "".join(r["_hex"] for r in truth)
    decoded_stream = "".join(r["_hex"] for r in decoded)
    return {
        "truth_frames": len(truth_frames),
        "found": len(found),
        "decoded_frames": len(decoded_frames),
        "true_frames": true_frames,
        "truth_bytes": len(truth_stream) // 2,
        "decoded_bytes": len(decoded_stream) // 2,
        "bytes_ok": 1 if truth_stream == decoded_stream else 0,
        "pairs": pairs,
        "paired": paired,
        "false_pairs": false_pairs,
        **timing,
        "runs": 1,
        "_t_errors": t_errors,
        "_misses": misses,
        "_false": false_frames,
        "_false_flags": false_flags,
    }


def score_files(truth_path, decoded_path):
    """score() of a truth file and a decoder's output file."""
    return score(load(truth_path), load(decoded_path), line_times(truth_path)[1])


def add(a, b):
    return {k: a.get(k, 0 if not k.startswith("_") else []) + b[k] for k in b}


def show_errors(s, limit, decoded):
    """Prints missed truth frames and false decoded frames with their decoded neighbours."""
    def brief(r):
        extra = r.get("faults", r.get("issues", r.get("cause", "")))
        return f"{r['kind']:5} @{r['_pos']:<7} t={r.get('t')} {r['_hex'][:48]} {extra}"
    for flag, d, silence in s["_false_flags"][:limit]:
        shown = "-" if silence is None else f"{silence * 1e3:.3f} ms"
        print(f"false {flag} flag: decoded {brief(d)}; truth silence before it {shown}")
    for title, items in (("missed truth frames", s["_misses"]), ("false decoded frames", s["_false"])):
        print(f"{title}: {len(items)}")
        for r in items[:limit]:
            print("  truth  " + brief(r) if title.startswith("missed") else "  decoded " + brief(r))
            near = [d for d in decoded if d["_pos"] + len(d["_hex"]) // 2 > r["_pos"] - 8
                    and d["_pos"] < r["_pos"] + len(r["_hex"]) // 2 + 8]
            for d in near:
                print("    decoded " + brief(d))


def ratio(n, d):
    return n / d if d else 1.0


def verdict(s, target):
    recall = ratio(s["found"], s["truth_frames"])
    precision = ratio(s["true_frames"], s["decoded_frames"])
    ok = (recall >= target and precision >= target and s["bytes_ok"] == s["runs"]
          and s["t35_false"] == 0 and s["t15_false"] == 0)
    return recall, precision, ok


def t_error_text(errors):
    if not errors:
        return "-"
    e = sorted(errors)
    return f"{e[len(e) // 2]:.3f}/{e[-1]:.3f}"


def pct(x):
    return f"{100 * x:.3f}%"


def print_table(rows):
    header = ("configuration", "runs", "frames", "recall", "precision", "bytes", "pairing",
              "false pairs", "t1.5 flagged", "t3.5 flagged", "false flags", "t error ms p50/max",
              "target", "result")
    lines = []
    passed = failed = 0
    for label, target, s in rows:
        recall, precision, ok = verdict(s, target)
        passed += ok
        failed += not ok
        lines.append((label, str(s["runs"]), str(s["truth_frames"]), pct(recall), pct(precision),
                      f"{s['bytes_ok']}/{s['runs']} ok", pct(ratio(s["paired"], s["pairs"])),
                      str(s["false_pairs"]), f"{s['t15_flagged']}/{s['t15_truth']}",
                      f"{s['t35_flagged']}/{s['t35_truth']}",
                      str(s["t15_false"] + s["t35_false"]), t_error_text(s["_t_errors"]), pct(target),
                      "pass" if ok else "FAIL"))
    widths = [max(len(r[i]) for r in [header] + lines) for i in range(len(header))]
    for r in [header] + lines:
        print("  ".join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in
                        enumerate(zip(r, widths))))
    print(f"accuracy: {passed} passed, {failed} failed")
    return failed == 0


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("truth", nargs="?")
    ap.add_argument("decoded", nargs="?")
    ap.add_argument("--target", type=float, default=0.999)
    ap.add_argument("--label", default="run")
    ap.add_argument("--manifest")
    ap.add_argument("--show", type=int, default=0, metavar="N",
                    help="list up to N missed and N false frames (single-run mode)")
    args = ap.parse_args(argv)
    if args.manifest:
        order = []
        totals = {}
        with open(args.manifest, encoding="utf-8") as f:
            for line in f:
                if not line.strip():
                    continue
                label, target, truth, decoded = line.rstrip("\n").split("\t")
                s = score_files(truth, decoded)
                if label not in totals:
                    order.append(label)
                    totals[label] = (float(target), s)
                else:
                    totals[label] = (totals[label][0], add(totals[label][1], s))
        rows = [(label, totals[label][0], totals[label][1]) for label in order]
        return 0 if print_table(rows) else 1
    if not args.truth or not args.decoded:
        ap.error("give TRUTH and DECODED, or --manifest")
    decoded = load(args.decoded)
    s = score(load(args.truth), decoded, line_times(args.truth)[1])
    if args.show:
        show_errors(s, args.show, decoded)
    return 0 if print_table([(args.label, args.target, s)]) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
