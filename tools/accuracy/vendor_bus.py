#!/usr/bin/env python3
"""A bus polled with a vendor function code (0x41: no length rule, so only silences, the
frames around a frame and the reads can end it), decoded by rtuscope and scored.

The master asks slave 7 with an 8-byte request, the slave answers with 10-43 bytes; some
transactions are FC03 polls instead (--mix). The traffic is seen as a host would see it:

  perbyte   one read per byte, stamped exactly;
  perframe  one read per frame, stamped at its last byte (an adapter that sends once the
            line goes idle, or a UART's character timeout);
  usb16     an FTDI-like adapter: the first byte into an empty buffer starts a 16 ms timer,
            62-byte packets;
  usb1      the same with a 1 ms timer and 32-byte packets.

With --faults R, a share R of the frames has one bit flipped on the wire (noise on the line:
the frame's CRC fails), drawn apart from the traffic, so the same seed sends the same frames
with and without faults.

  vendor_bus.py RTUSCOPE [--frames N] [--seeds 1,2] [--delivery perframe,usb16]
                [--gaps tight|normal|loose] [--mix] [--faults R] [--min-whole R]

Prints, per configuration, the frames sent, those damaged, the undamaged ones decoded whole
(CRC-valid, exactly their bytes), the damaged ones kept as one record of exactly their bytes,
the other records, the CRC-valid frames never sent, and the frames given a transaction.
With --min-whole, exits 1 when a configuration decodes fewer than that share of the
undamaged frames whole.
"""
import argparse
import json
import os
import random
import subprocess
import sys
import tempfile

# tools/pylib (modbus_crc), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../pylib"))
from modbus_crc import with_crc  # noqa: E402  (after the path line)

BAUD = 19200
CHAR_NS = 11 * 10**9 // BAUD
# Silence before an answer and before the next request, in character times [low, high).
GAPS = {"tight": ((2, 4), (3, 5)), "normal": ((4, 6), (5, 8)), "loose": ((4, 12), (30, 60))}


def traffic(frames, seed, gaps, mix, faults):
    """[(frame bytes, [byte end times], damaged)] on the wire."""
    rng = random.Random(seed)
    noise = random.Random(seed * 7919 + 1)  # its own stream: faults change no frame sent
    answer_gap, request_gap = GAPS[gaps]
    t = 10**6
    out = []
    for i in range(frames):
        request = i % 2 == 0
        if mix and (i // 2) % 3 == 0:
            body = bytes([7, 3, 0, 0, 0, 2]) if request else bytes([7, 3, 4]) + rng.randbytes(4)
        else:
            body = bytes([7, 0x41]) + rng.randbytes(4 if request else rng.randrange(6, 40))
        frame = with_crc(body)
        damaged = noise.random() < faults
        if damaged:
            flipped = bytearray(frame)
            flipped[noise.randrange(len(frame))] ^= 1 << noise.randrange(8)
            frame = bytes(flipped)
        t += rng.randrange(*(request_gap if request else answer_gap)) * CHAR_NS
        ends = []
        for _ in frame:
            t += CHAR_NS
            ends.append(t)
        out.append((frame, ends, damaged))
    return out


def reads(wire, delivery):
    """[(stamp, bytes)] as the host reads them."""
    if delivery == "perframe":
        return [(ends[-1], frame) for frame, ends, _ in wire]
    stream = [(end, b) for frame, ends, _ in wire for b, end in zip(frame, ends)]
    if delivery == "perbyte":
        return [(end, bytes([b])) for end, b in stream]
    latency, packet = (16 * 10**6, 62) if delivery == "usb16" else (10**6, 32)
    out = []
    k = 0
    while k < len(stream):
        deadline = stream[k][0] + latency
        j = k
        while j < len(stream) and stream[j][0] <= deadline and j - k < packet:
            j += 1
        stamp = stream[j - 1][0] if j - k == packet else deadline
        out.append((stamp, bytes(b for _, b in stream[k:j])))
        k = j
    return out


def write_hex(path, chunks):
    with open(path, "w", encoding="ascii") as f:
        f.write(f"# baud={BAUD} parity=E stop=1\n")
        for stamp, data in chunks:
            f.write(f"{stamp // 10**9}.{stamp % 10**9:09d} {data.hex(' ')}\n")


def score(rtuscope, path, wire):
    r = subprocess.run([rtuscope, "decode", path, "--format", "jsonl"], capture_output=True,
                       text=True, check=True)
    records = [json.loads(line) for line in r.stdout.splitlines() if line.strip()][1:]
    sent = {frame.hex() for frame, _, damaged in wire if not damaged}
    hurt = {frame.hex() for frame, _, damaged in wire if damaged}
    frames = [x for x in records if x["kind"] == "frame"]
    whole = sum(1 for x in frames if x["crc_ok"] and x["hex"] in sent)
    kept = sum(1 for x in frames if not x["crc_ok"] and x["hex"] in hurt)
    false = sum(1 for x in frames if x["crc_ok"] and x["hex"] not in sent)
    with_txn = sum(1 for x in frames if x.get("txn") is not None)
    return whole, kept, len(records) - whole - kept, false, with_txn


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("rtuscope")
    ap.add_argument("--frames", type=int, default=20000)
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--delivery", default="perbyte,perframe,usb16,usb1")
    ap.add_argument("--gaps", default="loose,normal,tight")
    ap.add_argument("--mix", action="store_true", help="one transaction in three is FC03")
    ap.add_argument("--faults", type=float, default=0.0,
                    help="share of frames with one bit flipped")
    ap.add_argument("--min-whole", type=float, default=None)
    args = ap.parse_args()
    failed = 0
    print(f"{'gaps':7} {'seed':>4} {'delivery':9} {'frames':>7} {'damaged':>7} {'whole':>7} "
          f"{'kept':>6} {'other':>6} {'false':>5} {'txn':>7}")
    with tempfile.TemporaryDirectory() as work:
        path = os.path.join(work, "bus.hex")
        for gaps in args.gaps.split(","):
            for seed in (int(s) for s in args.seeds.split(",")):
                wire = traffic(args.frames, seed, gaps, args.mix, args.faults)
                damaged = sum(1 for _, _, hurt in wire if hurt)
                for delivery in args.delivery.split(","):
                    write_hex(path, reads(wire, delivery))
                    whole, kept, other, false, with_txn = score(args.rtuscope, path, wire)
                    share = whole / (len(wire) - damaged)
                    bad = args.min_whole is not None and share < args.min_whole
                    failed += bad
                    below = f"  below {args.min_whole}" if bad else ""
                    print(f"{gaps:7} {seed:>4} {delivery:9} {len(wire):>7} {damaged:>7} "
                          f"{whole:>7} {kept:>6} {other:>6} {false:>5} {with_txn:>7}{below}")
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
