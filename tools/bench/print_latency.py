#!/usr/bin/env python3
"""Measures how soon `rtuscope live` prints a frame after its last byte left the wire.

rtuvbus (two endpoints) carries the traffic; this script writes frames on one endpoint
and `rtuscope live --format jsonl` reads the other. The bus log gives each burst's wire
end on the monotonic clock; the time this script reads the frame's line from rtuscope's
standard output is taken on the same clock. The difference is the print latency: the
quiet time rtuscope must see (t3.5 plus the port's timing resolution) plus scheduling.

usage: tools/bench/print_latency.py --rtuscope BUILD/rtuscope --vbus BUILD/tools/vbus/rtuvbus
                        [--baud 19200] [--count 200]
Prints min / median / p95 / max in ms for responses and for broadcast writes (a request
is printed together with its response, or at its timeout, so that it carries the pairing).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import termios
import time
import tty

# tools/pylib (modbus_crc), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../pylib"))
from modbus_crc import with_crc  # noqa: E402


def read_bus_log(path):
    """{hex of burst: [wire end, ...]} from the bus log (one line per write)."""
    ends = {}
    with open(path) as f:
        for line in f:
            if not line.strip() or line.startswith("#"):
                continue
            t, hexbytes = line.split()
            ends.setdefault(hexbytes, []).append(float(t))
    return ends


def summary(name, values):
    values = sorted(values)
    if not values:
        return f"{name}: none"
    p95 = values[min(len(values) - 1, int(0.95 * len(values)))]
    return (f"{name}: n={len(values)} min {values[0]:.2f} ms, median "
            f"{statistics.median(values):.2f} ms, p95 {p95:.2f} ms, max {values[-1]:.2f} ms")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--vbus", required=True)
    ap.add_argument("--baud", type=int, default=19200)
    ap.add_argument("--count", type=int, default=200)
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="rtuscope-latency-")
    log = os.path.join(work, "bus.hex")
    vbus = subprocess.Popen([args.vbus, "-n", "2", "--baud", str(args.baud), "--parity", "N",
                             "--log", log], stdout=subprocess.PIPE, text=True)
    writer_ep = vbus.stdout.readline().strip()
    sniff_ep = vbus.stdout.readline().strip()
    live = subprocess.Popen([args.rtuscope, "live", sniff_ep, "--baud", str(args.baud),
                             "--parity", "N", "--format", "jsonl", "--timeout-ms", "200"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                            bufsize=1)
    fd = os.open(writer_ep, os.O_RDWR | os.O_NOCTTY)
    tty.setraw(fd)
    time.sleep(0.5)  # rtuscope opens its port
    printed = []  # (monotonic time the line was read, record)
    for i in range(args.count):
        value = i & 0xFFFF
        if i % 2 == 0:
            request = with_crc([9, 3, 0, 0, 0, 2])
            response = with_crc([9, 3, 4, value >> 8, value & 0xFF, 0, 1])
            os.write(fd, request)
            time.sleep(0.008)
            os.write(fd, response)
            wanted = 2
        else:
            os.write(fd, with_crc([0, 6, 0, 1, value >> 8, value & 0xFF]))
            wanted = 1
        while wanted > 0:
            line = live.stdout.readline()
            now = time.monotonic()
            record = json.loads(line)
            if record.get("kind") == "frame":
                printed.append((now, record))
                wanted -= 1
        time.sleep(0.03)
    os.close(fd)
    live.terminate()
    live.wait(timeout=10)
    vbus.terminate()
    vbus.wait(timeout=10)

    ends = read_bus_log(log)
    responses, broadcasts = [], []
    for now, record in printed:
        # A burst can reach the bus log in several writes; the frame ends with the last.
        candidates = [t for t in ends.get(record["hex"], []) if t <= now]
        if not candidates:
            continue
        latency_ms = (now - max(candidates)) * 1e3
        if record.get("role") == "response":
            responses.append(latency_ms)
        elif record.get("slave") == 0:
            broadcasts.append(latency_ms)
    print(f"rtuscope live print latency at {args.baud} baud (t3.5 = "
          f"{(1.75 if args.baud > 19200 else 38.5e3 / args.baud):.2f} ms):")
    print(summary("  responses ", responses))
    print(summary("  broadcasts", broadcasts))


if __name__ == "__main__":
    sys.exit(main())
