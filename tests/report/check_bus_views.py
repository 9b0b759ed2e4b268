#!/usr/bin/env python3
"""Two captures of the same traffic must get the same diagnosis of the devices' timing.

Usage: check_bus_views.py RTUSCOPE WIRE_CAPTURE PINS_CAPTURE

WIRE_CAPTURE is the RS-485 line as a probe saw it, glitches of the undriven bus included;
PINS_CAPTURE is the same session at the UART pins, clean. Options in <capture>.args are
passed on. `rtuscope report --format json` of both must agree on:
  - each slave's responses_too_soon finding (present in both or in neither) and its count;
  - the master's turnaround: measured in both (not null), medians within MEDIAN_TOLERANCE_MS;
  - the slaves' latency medians, within the same tolerance;
  - no line_errors_one_device finding in either: framing errors of the floating bus at
    turnaround are not a device set to another baud rate or parity.
"""
import json
import os
import re
import shlex
import subprocess
import sys

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail  # noqa: E402  (after the path line)

# The two views time bytes from different channels of one recording: their edges differ by
# a few microseconds, far below this.
MEDIAN_TOLERANCE_MS = 0.1


def report(rtuscope, capture):
    options = []
    args_path = re.sub(r"\.[^.]+$", ".args", capture)
    if os.path.exists(args_path):
        with open(args_path, encoding="utf-8") as f:
            options = shlex.split(f.read())
    cmd = [rtuscope, "report", capture, "--format", "json"] + options
    result = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if result.returncode != 0:
        fail(f"{' '.join(cmd)} exited {result.returncode}: {result.stderr}")
    return json.loads(result.stdout)


def findings(rep, key):
    return [f for f in rep["findings"] if f["key"] == key]


def too_soon_by_slave(rep):
    return {f["slave"]: f["evidence"]["responses_too_soon"]
            for f in findings(rep, "responses_too_soon")}


def check_one(name, rep):
    """What each view must show on its own."""
    if rep["timing"]["master_turnaround_ms"] is None:
        fail(f"{name}: master turnaround not measured (null)")
    blamed = findings(rep, "line_errors_one_device")
    if blamed:
        fail(f"{name}: line_errors_one_device blames a device: {blamed[0]['summary']}")
    if not too_soon_by_slave(rep):
        fail(f"{name}: no responses_too_soon finding")


def close(a, b):
    return abs(a - b) <= MEDIAN_TOLERANCE_MS


def check_agree(wire, pins):
    if too_soon_by_slave(wire) != too_soon_by_slave(pins):
        fail(f"responses_too_soon differs: wire {too_soon_by_slave(wire)}, "
             f"pins {too_soon_by_slave(pins)}")
    wire_turn = wire["timing"]["master_turnaround_ms"]
    pins_turn = pins["timing"]["master_turnaround_ms"]
    if not close(wire_turn["p50"], pins_turn["p50"]):
        fail(f"master turnaround p50 differs: wire {wire_turn['p50']} ms, "
             f"pins {pins_turn['p50']} ms")
    if set(wire["slaves"]) != set(pins["slaves"]):
        fail(f"slaves differ: wire {sorted(wire['slaves'])}, pins {sorted(pins['slaves'])}")
    for addr, slave in wire["slaves"].items():
        a, b = slave["latency_ms"], pins["slaves"][addr]["latency_ms"]
        if (a is None) != (b is None) or (a is not None and not close(a["p50"], b["p50"])):
            fail(f"slave {addr} latency differs: wire {a}, pins {b}")


def main():
    if len(sys.argv) != 4:
        fail("usage: check_bus_views.py RTUSCOPE WIRE_CAPTURE PINS_CAPTURE")
    rtuscope, wire_path, pins_path = (os.path.abspath(p) for p in sys.argv[1:])
    wire = report(rtuscope, wire_path)
    pins = report(rtuscope, pins_path)
    check_one("wire view", wire)
    check_one("pins view", pins)
    check_agree(wire, pins)
    print(f"ok: {os.path.basename(wire_path)} and {os.path.basename(pins_path)} agree: "
          f"responses_too_soon {too_soon_by_slave(wire)}, master turnaround p50 "
          f"{wire['timing']['master_turnaround_ms']['p50']} / "
          f"{pins['timing']['master_turnaround_ms']['p50']} ms, no device blamed for line errors")


if __name__ == "__main__":
    main()
