#!/usr/bin/env python3
"""`rtuscope demo` end to end: the virtual bus, the simulated devices' traffic, live capture
through the real serial path, device maps, the end-of-run report.

Checks that the demo printed exactly the records that decoding the bundled traffic file
gives (same bytes, same roles, same pairing verdicts), that device points are named, and
that its report names the four devices and counts the same frames.
"""
import argparse
import json
import os
import shutil
import subprocess

from bus_helpers import fail


def jsonl(text):
    return [json.loads(line) for line in text.splitlines() if line.strip()]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--work", required=True)
    args = ap.parse_args()
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    report_path = os.path.join(args.work, "demo.json")
    capture = os.path.join(args.work, "demo.pcapng")
    demo = subprocess.run([args.rtuscope, "demo", "--format", "jsonl", "--report", report_path,
                           "-w", capture], capture_output=True, text=True, timeout=120)
    if demo.returncode != 0:
        fail(f"demo exited {demo.returncode}: {demo.stderr}")
    print(demo.stderr, end="")
    traffic = os.path.join(args.source, "captures", "demo_four_devices.hex")
    bus = os.path.join(args.source, "captures", "demo_four_devices.bus.toml")
    decoded = subprocess.run([args.rtuscope, "decode", traffic, "--bus", bus, "--format",
                              "jsonl"], capture_output=True, text=True, timeout=60)
    if decoded.returncode != 0:
        fail(f"decode {traffic}: {decoded.stderr}")

    def body(records):
        return [r for r in records if r["kind"] in ("frame", "noise")]

    live = body(jsonl(demo.stdout))
    want = body(jsonl(decoded.stdout))
    if [r["hex"] for r in live] != [r["hex"] for r in want]:
        fail(f"demo printed {len(live)} records, the traffic file has {len(want)}; "
             "their bytes differ")
    for got, expected in zip(live, want):
        for key in ("role", "slave", "fc", "crc_ok"):
            if got.get(key) != expected.get(key):
                fail(f"{key} differs: demo {got}\n decode {expected}")
        if ("timeout" in (got.get("issues") or [])) != ("timeout" in (expected.get("issues") or [])):
            fail(f"timeout verdict differs: demo {got}\n decode {expected}")
    named = [r for r in live if r.get("registers")]
    if not named:
        fail("no frame carries named device registers")

    with open(report_path) as f:
        report = json.load(f)
    models = {addr: s.get("device") for addr, s in report["slaves"].items()}
    if models != {"1": "yw2050", "2": "yw2300", "3": "th900", "4": "yakotec"}:
        fail(f"report models: {models}")
    frames = sum(1 for r in live if r["kind"] == "frame")
    if report["totals"]["frames"] != frames:
        fail(f"report counts {report['totals']['frames']} frames, the demo printed {frames}")
    if not report["findings"]:
        fail("the demo's traffic has faults, but the report found nothing")

    replay = subprocess.run([args.rtuscope, "decode", capture, "--format", "jsonl"],
                            capture_output=True, text=True, timeout=60)
    if replay.returncode != 0 or [r["hex"] for r in body(jsonl(replay.stdout))] != \
            [r["hex"] for r in live]:
        fail(f"the demo's recording does not replay to the same records: {replay.stderr}")
    print(f"OK: {len(live)} records as decoded from the file, {len(named)} with named "
          f"registers; report: {frames} frames, models {models}, "
          f"{len(report['findings'])} findings")


if __name__ == "__main__":
    main()
