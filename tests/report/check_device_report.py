#!/usr/bin/env python3
"""`rtuscope report` on a simulated device capture (captures/sim_<model>.hex): the slaves
are named and their register values named and scaled by the device maps.

With the capture's options (<name>.args: --device or --bus) every slave shows the model
the options give, marked "configured"; the CSV export holds exactly the values `rtuscope
decode` shows for the same options (point name, value, unit, at the response's time), and
the JSON points agree with the CSV. Without any option the same models are identified
from the traffic, marked "identified", and the CSV is the same; with --no-identify, or a
sample of first frames too small to be sure (--identify-frames), the slaves have no model
and raw registers. Run from the source tree
(the .args name files relative to it).
"""
import csv
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail  # noqa: E402  (after the path line)


RAW_POINT = re.compile(r"(holding|input|coil|discrete) 0x[0-9A-F]{4}")


def run(cmd):
    result = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if result.returncode != 0:
        fail(f"{' '.join(cmd)} exited {result.returncode}: {result.stderr}")
    return result.stdout


def configured_models(args):
    """slave → model from --device ADDR=MODEL and the [slaves] of a --bus file."""
    models = {}
    for i, a in enumerate(args):
        if a == "--device":
            addr, model = args[i + 1].split("=", 1)
            models[addr] = model
        if a == "--bus":
            in_slaves = False
            for line in open(args[i + 1], encoding="utf-8"):
                line = line.split("#", 1)[0].strip()
                if line.startswith("["):
                    in_slaves = line == "[slaves]"
                elif in_slaves and "=" in line:
                    addr, model = line.split("=", 1)
                    models[addr.strip()] = model.strip().strip('"')
    return models


def decoded_values(rtuscope, capture, args):
    """(time, slave, point, value, unit) that `decode` shows for confirmed exchanges:
    reads on their response, writes (registers decoded on the request) at the response."""
    out = []
    requests = {}
    for line in run([rtuscope, "decode", capture, "--format", "jsonl"] + args).splitlines():
        rec = json.loads(line)
        if rec.get("kind") != "frame" or not rec.get("crc_ok"):
            continue
        if rec.get("role") == "request":
            requests[rec.get("txn")] = rec
            continue
        if rec.get("role") != "response" or rec.get("exception") is not None:
            continue
        fc = rec["fc"]
        source = rec if fc in (1, 2, 3, 4) else requests.get(rec.get("txn"), {})
        if fc not in (1, 2, 3, 4, 5, 6, 15, 16):
            continue
        t = f"{rec['t']:.9f}"[:-3]  # the CSV's six decimals, truncated
        for reg in source.get("registers", []):
            if reg.get("value") is None:  # spare, partial, or a scale nobody knows
                continue
            out.append((t, str(rec["slave"]), reg["name"], float(reg["value"]),
                        reg.get("unit") or "", float(reg["value"]) != float(reg["raw"])))
    return out


def csv_values(path):
    with open(path, encoding="utf-8", newline="") as f:
        rows = list(csv.reader(f))
    if rows[0] != ["time", "slave", "point", "value", "unit"]:
        fail(f"CSV header is {rows[0]}")
    return [(r[0], r[1], r[2], float(r[3]), r[4]) for r in rows[1:]]


def same_values(a, b):
    if len(a) != len(b):
        return False
    for x, y in zip(a, b):
        if x[:3] != y[:3] or x[4] != y[4] or abs(x[3] - y[3]) > 1e-9 * max(1.0, abs(x[3])):
            return False
    return True


def noise_first(capture, work, count):
    """A copy of the text hex `capture` with `count` bytes of noise (one read each, a byte
    that starts no frame: address 0xF9 and a function code outside Modbus) one second before
    its traffic, which moves one second later."""
    path = os.path.join(work, "noise-first.hex")
    with open(capture, encoding="ascii") as src, open(path, "w", encoding="ascii") as out:
        lines = src.read().splitlines()
        header = [line for line in lines if line.startswith("#")]
        data = [line for line in lines if line and not line.startswith("#")]
        out.write("\n".join(header) + "\n")
        for i in range(count):
            out.write(f"{0.5 + i * 0.0012:.9f} {0xF9 if i % 2 == 0 else 0xFE:02x}\n")
        for line in data:
            t, rest = line.split(" ", 1)
            out.write(f"{float(t) + 1.0:.9f} {rest}\n")
    return path


def report(rtuscope, capture, args, work, tag):
    csv_path = os.path.join(work, f"{tag}.csv")
    js = json.loads(run([rtuscope, "report", capture, "--format", "json", "--csv", csv_path]
                        + args))
    return js, csv_values(csv_path)


def check_sample(js, wanted, ended, frames=None, noise_bytes=None):
    """The report's `identification`: asked for `wanted` frames (0: all), ended for the
    reason `ended`; it looked at `frames` frames and `noise_bytes` bytes of noise where
    given, and on `enough` at least as much as it was asked for, but no frame more."""
    sample = js["identification"]
    if sample is None:
        fail("the report does not say what identification looked at")
    if sample["frames_wanted"] != wanted or sample["ended"] != ended:
        fail(f"identification {sample}: expected {wanted} frames wanted, ended {ended!r}")
    if frames is not None and sample["frames"] != frames:
        fail(f"identification {sample} looked at other than {frames} frames")
    if noise_bytes is not None and sample["noise_bytes"] != noise_bytes:
        fail(f"identification {sample} looked at other than {noise_bytes} bytes of noise")
    if ended == "enough" and not (sample["frames"] <= wanted
                                  <= sample["frames"] + sample["noise_bytes"]):
        fail(f"identification {sample} ended on enough with other than {wanted} frames")


def without_sample(js):
    """The report less what identification looked at (its sample's size differs)."""
    return {k: v for k, v in js.items() if k != "identification"}


def main():
    rtuscope, capture = sys.argv[1:]
    args_path = re.sub(r"\.[^.]+$", ".args", capture)
    if not os.path.exists(args_path):
        fail(f"{capture} has no {args_path}")
    args = shlex.split(open(args_path, encoding="utf-8").read())
    models = configured_models(args)
    if not models:
        fail(f"{args_path} names no slave")
    with tempfile.TemporaryDirectory(prefix="rtuscope-device-report-") as work:
        check(rtuscope, capture, args, models, work)


def check(rtuscope, capture, args, models, work):

    js, rows = report(rtuscope, capture, args, work, "configured")
    for addr, model in models.items():
        slave = js["slaves"].get(addr)
        if slave is None:
            fail(f"no slave {addr} in the report")
        if slave["device"] != model or slave["device_model_source"] != "configured":
            fail(f"slave {addr}: device {slave['device']!r} ({slave['device_model_source']}),"
                 f" expected {model!r} (configured)")
    decoded = decoded_values(rtuscope, capture, args)
    expected = [d[:5] for d in decoded]
    scaled = sorted({d[2] for d in decoded if d[5]})  # value differs from the raw register
    if not expected:
        fail("decode shows no named value for this capture")
    if not same_values(rows, expected):
        diff = next((i for i, (x, y) in enumerate(zip(rows, expected)) if x != y),
                    min(len(rows), len(expected)))
        fail(f"CSV ({len(rows)} values) differs from decode ({len(expected)}) at value {diff}: "
             f"{rows[diff:diff + 1]} vs {expected[diff:diff + 1]}")
    if any(RAW_POINT.fullmatch(r[2]) for r in rows):
        fail("a mapped slave's values are still raw registers")
    # The JSON points summarise the same values.
    for p in js["points"]:
        mine = [r for r in rows if r[1] == str(p["slave"]) and r[2] == p["point"]]
        if len(mine) != p["samples"] or mine[-1][4] != p["unit"]:
            fail(f"JSON point {p} does not match its {len(mine)} CSV rows")
        if abs(mine[-1][3] - p["last"]) > 1e-9 * max(1.0, abs(p["last"])):
            fail(f"JSON point {p['point']} last {p['last']} != CSV {mine[-1][3]}")
        if min(r[3] for r in mine) != p["min"] or max(r[3] for r in mine) != p["max"]:
            fail(f"JSON point {p['point']} min/max differ from the CSV")
    units = sorted({r[4] for r in rows if r[4]})

    # Without options: the same models, identified, and the same values.
    js_id, rows_id = report(rtuscope, capture, [], work, "identified")
    for addr, model in models.items():
        slave = js_id["slaves"][addr]
        if slave["device"] != model or slave["device_model_source"] != "identified":
            fail(f"slave {addr} without options: {slave['device']!r} "
                 f"({slave['device_model_source']}), expected {model!r} (identified)")
    if not same_values(rows_id, rows):
        fail("identified models give other values than configured ones")
    # The report says what the models rest on: here the whole capture, shorter than a sample.
    totals = js_id["totals"]
    check_sample(js_id, 200000, "capture_end", totals["frames"], totals["noise_bytes"])
    # --no-identify: no model, raw registers.
    js_raw, rows_raw = report(rtuscope, capture, ["--no-identify"], work, "raw")
    for addr in models:
        if js_raw["slaves"][addr]["device"] is not None:
            fail(f"slave {addr} has a model despite --no-identify")
    if js_raw["identification"] is not None:
        fail(f"--no-identify reports an identification: {js_raw['identification']}")
    if not rows_raw or not all(RAW_POINT.fullmatch(r[2]) for r in rows_raw):
        fail("--no-identify does not leave raw registers")
    # Identification looks at a sample of first frames: 8 frames hold fewer requests than a
    # confident model needs, so the slaves keep raw registers; 0 means the whole capture.
    js_few, _ = report(rtuscope, capture, ["--identify-frames", "8"], work, "few")
    for addr in models:
        if js_few["slaves"][addr]["device"] is not None:
            fail(f"slave {addr} identified from 8 frames")
    check_sample(js_few, 8, "enough")
    js_all, rows_all = report(rtuscope, capture, ["--identify-frames", "0"], work, "all")
    check_sample(js_all, 0, "capture_end", totals["frames"], totals["noise_bytes"])
    if without_sample(js_all) != without_sample(js_id) or rows_all != rows_id:
        fail("--identify-frames 0 (the whole capture) differs from the default sample")
    # Noise counts towards the sample a frame per byte: framing it is the dearest work there
    # is, and a sick bus must not be framed twice before its first frames. Behind 300 noise
    # bytes, a sample of 200 ends in the noise; the whole capture still identifies.
    noisy = noise_first(capture, work, 300)
    js_noisy, _ = report(rtuscope, noisy, ["--identify-frames", "200"], work, "noisy")
    for addr in models:
        if js_noisy["slaves"][addr]["device"] is not None:
            fail(f"slave {addr} identified from a sample of 200 that 300 noise bytes fill")
    if js_noisy["totals"]["noise_bytes"] < 300:
        fail(f"the noise before the traffic was not read as noise: {js_noisy['totals']}")
    check_sample(js_noisy, 200, "enough", 0)
    js_noisy_all, _ = report(rtuscope, noisy, ["--identify-frames", "0"], work, "noisy-all")
    for addr, model in models.items():
        if js_noisy_all["slaves"][addr]["device"] != model:
            fail(f"slave {addr} not identified as {model} behind the noise from the whole "
                 "capture")
    text = run([rtuscope, "report", capture])
    for addr, model in models.items():
        if not re.search(rf"^\s+{addr} {re.escape(model)}\*\s", text, re.M):
            fail(f"text report does not show slave {addr} as {model}* (identified)")
    said = f"models identified from all {totals['frames']} frames"
    if said not in text:
        fail(f"text report does not say what identification looked at ({said!r})")
    print(f"ok: {capture}: models {models}, {len(rows)} values as decode shows them, "
          f"scaled: {scaled}, units {units}; identified without options")


if __name__ == "__main__":
    main()
