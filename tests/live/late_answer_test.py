#!/usr/bin/env python3
"""Live ≡ replay where a request's fate is decided by the clock: answers around the response
timeout, on the virtual bus (rtuvbus), plain and through a USB adapter model.

A master (endpoint 0) polls a slave (endpoint 1) that answers after delays from well inside
`rtuscope live --timeout-ms 100` to well past it, some just past it (inside the 20 ms an
adapter may still hold bytes), and now and then not at all. Live decides a timeout while the
line is quiet; the replay of its recording sees no quiet moments. Checked:
  * `decode` of the recording gives exactly the live records;
  * answers well inside the timeout are paired (one txn), answers well past it are `late`
    and unpaired, their request `timeout`; unanswered requests are `timeout`;
  * every byte written is in the records.
"""
import argparse
import json
import os
import signal
import subprocess
import sys
import time

from bus_helpers import fail, open_endpoint, stop_all

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fresh_dir  # noqa: E402
from modbus_crc import with_crc  # noqa: E402

BAUD = 19200
TIMEOUT_MS = 100
# Answer delays after the request, ms: paired, paired, just past the timeout (either way,
# but the same live and replayed), late, late, and no answer.
DELAYS_MS = [20, 80, 104, 112, 140, 260, None]


def load_jsonl(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def talk(master_ep, slave_ep, rounds):
    master = open_endpoint(master_ep)
    slave = open_endpoint(slave_ep)
    written = []
    char_s = 11 / BAUD
    try:
        for n in range(rounds):
            delay = DELAYS_MS[n % len(DELAYS_MS)]
            request = with_crc(bytes([0x11, 0x03, 0x00, n % 100, 0x00, 0x02]))
            os.write(master, request)
            written.append(request)
            sent = time.monotonic()
            if delay is not None:
                # The delay counts from the request's last byte on the wire.
                time.sleep(max(0.0, sent + len(request) * char_s + delay / 1000 - time.monotonic()))
                response = with_crc(bytes([0x11, 0x03, 0x04, n & 0xFF, 0x01, 0x02, 0x03]))
                os.write(slave, response)
                written.append(response)
            time.sleep(0.35)  # past any answer, and past the timeout of an unanswered one
    finally:
        os.close(master)
        os.close(slave)
    return written


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--vbus", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--usb-latency-ms", type=float)
    ap.add_argument("--rounds", type=int, default=28)
    args = ap.parse_args()
    fresh_dir(args.work)
    pcapng = os.path.join(args.work, "live.pcapng")
    live_out = os.path.join(args.work, "live.jsonl")

    vbus_cmd = [args.vbus, "-n", "3", "--baud", str(BAUD), "--parity", "E"]
    if args.usb_latency_ms is not None:
        vbus_cmd += ["--usb", "2", "--usb-latency-ms", str(args.usb_latency_ms)]
    vbus = subprocess.Popen(vbus_cmd, stdout=subprocess.PIPE, text=True)
    procs = [vbus]
    try:
        eps = [vbus.stdout.readline().strip() for _ in range(3)]
        live = subprocess.Popen([args.rtuscope, "live", eps[2], "--baud", str(BAUD), "--parity",
                                 "E", "--timeout-ms", str(TIMEOUT_MS), "--format", "jsonl", "-o",
                                 live_out, "-w", pcapng], stderr=subprocess.PIPE, text=True)
        procs.append(live)
        while "listening on" not in (line := live.stderr.readline()):
            if not line:
                fail(f"rtuscope live ended early (exit {live.wait()})")
        written = talk(eps[0], eps[1], args.rounds)
        time.sleep(0.3)
        live.send_signal(signal.SIGTERM)
        _, err = live.communicate(timeout=20)
        if live.returncode != 0:
            fail(f"rtuscope live exited {live.returncode}: {err}")
    finally:
        stop_all(procs)

    body = [r for r in load_jsonl(live_out) if r["kind"] in ("frame", "noise")]
    if "".join(r["hex"] for r in body) != "".join(w.hex() for w in written):
        fail("the live records do not hold exactly the bytes written")
    replay = subprocess.run([args.rtuscope, "decode", pcapng, "--format", "jsonl"],
                            capture_output=True, text=True, timeout=60)
    if replay.returncode != 0:
        fail(f"decode {pcapng}: {replay.stderr}")
    rbody = [json.loads(line) for line in replay.stdout.splitlines() if line.strip()]
    rbody = [r for r in rbody if r["kind"] in ("frame", "noise")]
    for i, (a, b) in enumerate(zip(body, rbody)):
        if a != b:
            fail(f"record {i}: replay differs:\n live   {a}\n replay {b}")
    if len(rbody) != len(body):
        fail(f"replay has {len(rbody)} records, live {len(body)}")

    paired = late = unanswered = 0
    frames = [r for r in body if r["kind"] == "frame"]
    for i, f in enumerate(frames):
        issues = f.get("issues") or []
        if f["role"] == "response":
            request = frames[i - 1]
            if f["latency_ms"] < TIMEOUT_MS - 10:
                if f["txn"] is None or f["txn"] != request["txn"] or "late" in issues:
                    fail(f"an answer after {f['latency_ms']} ms is not paired: {request} / {f}")
                paired += 1
            elif f["latency_ms"] > TIMEOUT_MS + 25:
                req_issues = request.get("issues") or []
                if "late" not in issues or f["txn"] is not None or "timeout" not in req_issues \
                        or request["txn"] is not None:
                    fail(f"an answer after {f['latency_ms']} ms is not late and unpaired: "
                         f"{request} / {f}")
                late += 1
        elif f["role"] == "request":
            answered = i + 1 < len(frames) and frames[i + 1]["role"] == "response"
            if not answered:
                if "timeout" not in (f.get("issues") or []):
                    fail(f"an unanswered request is not a timeout: {f}")
                unanswered += 1
    if paired == 0 or late == 0 or unanswered == 0:
        fail(f"the traffic did not show every case: {paired} paired, {late} late, "
             f"{unanswered} unanswered")
    print(f"OK: {len(body)} records, replay identical; {paired} paired, {late} late and "
          f"unpaired, {unanswered} unanswered")


if __name__ == "__main__":
    main()
