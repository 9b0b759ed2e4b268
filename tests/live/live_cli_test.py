#!/usr/bin/env python3
"""`rtuscope live` as a user meets it, on virtual buses (rtuvbus):

  wrong_port   a port that does not exist: a clear message naming it, exit status 2;
  kill9        `kill -9` during a recording: the pcapng is readable by rtuscope and by
               tshark, and holds every frame that was on the wire more than a second
               before the kill;
  two_ports    the two directions of a link on two adapters (two buses: the master's line
               and the slave's line): merged by time, requests paired with responses, the
               recording has one interface per port with the direction flags, and it
               replays to the same records.
"""
import argparse
import json
import os
import select
import shutil
import signal
import subprocess
import sys
import time

from bus_helpers import fail, open_endpoint, stop_all

# tools/pylib (modbus_crc), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from modbus_crc import with_crc  # noqa: E402

BAUD = 19200






def start_bus(vbus, n, log):
    proc = subprocess.Popen([vbus, "-n", str(n), "--baud", str(BAUD), "--parity", "N",
                             "--log", log], stdout=subprocess.PIPE, text=True)
    return proc, [proc.stdout.readline().strip() for _ in range(n)]




def wait_listening(proc, deadline=20.0):
    end = time.monotonic() + deadline
    while time.monotonic() < end:
        line = proc.stderr.readline()
        if not line:
            break
        if "listening on" in line:
            return
    fail("rtuscope live did not start listening")


def bus_log(path):
    """[(wire end, hex)] of every write the bus carried."""
    out = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                t, hexbytes = line.split()
                out.append((float(t), hexbytes))
    return out


def read_exactly(fd, count, deadline=10.0):
    """`count` bytes from `fd`, or fewer if the deadline passes first."""
    got = b""
    end = time.monotonic() + deadline
    while len(got) < count:
        left = end - time.monotonic()
        if left <= 0 or not select.select([fd], [], [], left)[0]:
            break
        got += os.read(fd, count - len(got))
    return got


def decode(rtuscope, path):
    r = subprocess.run([rtuscope, "decode", path, "--format", "jsonl"], capture_output=True,
                       text=True, timeout=60)
    if r.returncode != 0:
        fail(f"decode {path}: exit {r.returncode}: {r.stderr}")
    return [json.loads(l) for l in r.stdout.splitlines() if l.strip()]




def wrong_port(args):
    missing = os.path.join(args.work, "no-such-port")
    r = subprocess.run([args.rtuscope, "live", missing], capture_output=True, text=True,
                       timeout=30)
    if r.returncode != 2 or missing not in r.stderr:
        fail(f"live on a missing port: exit {r.returncode}, said: {r.stderr}")
    print(f"OK: {r.stderr.strip()}")


def kill9(args):
    log = os.path.join(args.work, "bus.hex")
    capture = os.path.join(args.work, "killed.pcapng")
    bus, (master, sniff) = start_bus(args.vbus, 2, log)
    procs = [bus]
    try:
        live = subprocess.Popen([args.rtuscope, "live", sniff, "--baud", str(BAUD), "--parity",
                                 "N", "-w", capture, "-o", os.devnull],
                                stderr=subprocess.PIPE, text=True)
        procs.append(live)
        wait_listening(live)
        fd = open_endpoint(master)
        end = time.monotonic() + 3.0
        i = 0
        while time.monotonic() < end:
            os.write(fd, with_crc([0, 6, 0, 1, (i >> 8) & 0xFF, i & 0xFF]))  # broadcasts
            i += 1
            time.sleep(0.05)
        live.send_signal(signal.SIGKILL)
        killed_at = time.monotonic()
        live.wait(timeout=10)
        os.close(fd)
    finally:
        stop_all(procs)
    records = decode(args.rtuscope, capture)
    got = {r["hex"] for r in records if r["kind"] == "frame"}
    must = [h for t, h in bus_log(log) if t < killed_at - 1.0]
    lost = [h for h in must if h not in got]
    if not must or lost:
        fail(f"{len(lost)} of {len(must)} frames older than 1 s before the kill are missing")
    if shutil.which("tshark"):
        r = subprocess.run(["tshark", "-r", capture], capture_output=True, text=True,
                           timeout=60)
        if r.returncode != 0:
            fail(f"tshark cannot read the killed recording: {r.stderr}")
    print(f"OK: killed after {i} frames; the file holds {len(got)}, all {len(must)} "
          f"older than 1 s among them")


def two_ports(args):
    log_a = os.path.join(args.work, "master_line.hex")
    log_b = os.path.join(args.work, "slave_line.hex")
    capture = os.path.join(args.work, "two.pcapng")
    out = os.path.join(args.work, "two.jsonl")
    # Each line has a third endpoint where the other side listens: the slave answers only
    # once its line has carried the whole request, and the master asks again only once the
    # answer has been carried, as on a real link. A stall of this machine then delays the
    # exchange but cannot squeeze two requests into one burst ahead of their answers, which
    # would be a different bus from the one the expectations below describe.
    bus_a, (master, tap_a, slave_rx) = start_bus(args.vbus, 3, log_a)
    bus_b, (slave, tap_b, master_rx) = start_bus(args.vbus, 3, log_b)
    procs = [bus_a, bus_b]
    pairs = 20
    try:
        live = subprocess.Popen([args.rtuscope, "live", tap_a, tap_b, "--baud", str(BAUD),
                                 "--parity", "N", "--format", "jsonl", "-o", out, "-w",
                                 capture, "--timeout-ms", "200"],
                                stderr=subprocess.PIPE, text=True)
        procs.append(live)
        wait_listening(live)
        fa, fb = open_endpoint(master), open_endpoint(slave)
        heard_a, heard_b = open_endpoint(slave_rx), open_endpoint(master_rx)
        for i in range(pairs):
            request = with_crc([5, 3, 0, i, 0, 1])
            os.write(fa, request)
            if read_exactly(heard_a, len(request)) != request:
                fail(f"the master's line did not carry request {i} whole")
            time.sleep(0.02)  # the slave's turnaround: room for a stall of the listener too
            response = with_crc([5, 3, 2, 0, i])
            os.write(fb, response)
            if read_exactly(heard_b, len(response)) != response:
                fail(f"the slave's line did not carry response {i} whole")
            time.sleep(0.03)
        time.sleep(0.3)
        live.send_signal(signal.SIGTERM)
        live.wait(timeout=20)
        if live.returncode != 0:
            fail(f"live exited {live.returncode}")
        for fd in (fa, fb, heard_a, heard_b):
            os.close(fd)
    finally:
        stop_all(procs)
    with open(out) as f:
        records = [json.loads(l) for l in f if l.strip()]
    frames = [r for r in records if r["kind"] == "frame"]
    requests = [r for r in frames if r["role"] == "request"]
    responses = [r for r in frames if r["role"] == "response" and r.get("txn") is not None]
    if len(frames) != 2 * pairs or len(requests) != pairs or len(responses) != pairs:
        fail(f"{len(frames)} frames, {len(requests)} requests, {len(responses)} paired "
             f"responses; expected {pairs} of each")
    for req, resp in zip(requests, responses):
        if req["txn"] != resp["txn"] or req["addr"] != resp.get("addr"):
            fail(f"pairing: {req} / {resp}")
    replayed = [r for r in decode(args.rtuscope, capture) if r["kind"] in ("frame", "noise")]
    body = [r for r in records if r["kind"] in ("frame", "noise")]
    if replayed != body:
        fail("the two-port recording does not replay to the same records")
    if shutil.which("tshark"):
        r = subprocess.run(["tshark", "-r", capture, "-T", "fields", "-e",
                            "frame.interface_id", "-e", "frame.packet_flags_direction"],
                           capture_output=True, text=True, timeout=60)
        # pcapng direction flags: 2 = outbound (the master's line), 1 = inbound.
        seen = {tuple(int(v, 0) for v in l.split("\t")) for l in r.stdout.splitlines()
                if l.strip()}
        if not {(0, 2), (1, 1)} <= seen:
            fail(f"interfaces/directions in the recording: {sorted(seen)}")
    print(f"OK: {pairs} requests on one port paired with {pairs} responses on the other; "
          f"replay identical")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--vbus", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--scenario", required=True,
                    choices=["wrong_port", "kill9", "two_ports"])
    args = ap.parse_args()
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    globals()[args.scenario](args)


if __name__ == "__main__":
    main()
