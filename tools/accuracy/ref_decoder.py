#!/usr/bin/env python3
"""A deliberately small reference decoder for Modbus RTU captures: a baseline for rtuscope.

It reads rtusim's text hex capture ("# baud=…" header, then "TIME HH HH …" lines) and
writes JSON lines that tools/accuracy/score.py understands. It shares no code with rtuscope
and knows nothing of the simulator's truth.

Framing is CRC resynchronisation and nothing else: at each byte position it takes the
shortest run of bytes that has a plausible length for its function code (request or
response shape, byte-count fields included; any length for codes without a fixed shape)
and a valid CRC. When there is none, the byte is noise and the search moves on by one.
Consecutive noise bytes form one noise record, split where the timestamps show a silence
of t3.5 or more (the only use of time besides the records' start times). Pairing: a frame
right after a request, from the same slave with the same function code (or its exception),
that fits the response shape, is that request's response.

  ref_decoder.py CAPTURE.hex > DECODED.jsonl
"""
import json
import os
import sys

# tools/pylib (modbus_crc), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../pylib"))
from modbus_crc import CRC_INIT, crc16  # noqa: E402
from rtu_timing import char_seconds, t3_5_seconds  # noqa: E402

MAX_ADU = 256


def read_capture(path):
    """(baud, bits per character, bytes, end time in s of each byte as the reads place it)."""
    baud, bits = 9600, 11
    data = bytearray()
    ends = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if line.startswith("#"):
                fields = dict(x.split("=", 1) for x in line[1:].split() if "=" in x)
                if "baud" in fields:
                    baud = int(fields["baud"])
                    bits = 1 + 8 + (fields.get("parity", "E") != "N") + int(fields.get("stop", 1))
                continue
            if not line:
                continue
            t, *values = line.split()
            chunk = bytes.fromhex("".join(values))
            # A read returns bytes that arrived back to back, the last one just before it.
            ct = bits / baud
            for k in range(len(chunk)):
                ends.append(float(t) - (len(chunk) - 1 - k) * ct)
            data += chunk
    return baud, bits, bytes(data), ends


def shapes(buf, i):
    """(request lengths, response lengths) allowed at position i; None = any length."""
    n = len(buf)

    def at(k):
        return buf[i + k] if i + k < n else None

    def plus(base, k):
        v = at(k)
        return [] if v is None else [base + v]

    fc = at(1)
    if fc is None or buf[i] > 247 or fc == 0:
        return [], []
    if fc & 0x80:
        return [], [5]
    if fc in (1, 2, 3, 4):
        return [8], plus(5, 2)
    if fc in (5, 6):
        return [8], [8]
    if fc == 7:
        return [4], [5]
    if fc == 0x0B:
        return [4], [8]
    if fc in (0x0C, 0x11):
        return [4], plus(5, 2)
    if fc in (0x0F, 0x10):
        return plus(9, 6), [8]
    if fc in (0x14, 0x15):
        return plus(5, 2), plus(5, 2)
    if fc == 0x16:
        return [10], [10]
    if fc == 0x17:
        return plus(13, 10), plus(5, 2)
    if fc == 0x18:
        hi, lo = at(2), at(3)
        return [6], ([] if hi is None or lo is None else [6 + (hi << 8 | lo)])
    return None, None  # diagnostics, MEI, user-defined codes: no fixed shape


def frame_at(buf, i):
    """Length of the shortest plausible CRC-valid frame at i, or None."""
    req, resp = shapes(buf, i)
    if req is None:
        candidates = set(range(4, MAX_ADU + 1))
    else:
        candidates = set(req) | set(resp)
    # One running CRC, continued from each candidate length to the next: over a whole
    # frame, CRC included, it is 0.
    crc, done = CRC_INIT, 0
    for length in sorted(c for c in candidates if c <= len(buf) - i):
        crc = crc16(buf[i + done:i + length], crc)
        done = length
        if crc == 0:
            return length
    return None


def fits(buf, i, length):
    """(fits the request shape, fits the response shape) of a frame found at i."""
    req, resp = shapes(buf, i)
    if req is None:
        return True, True
    return length in req, length in resp


def decode(baud, bits, buf, ends):
    ct = char_seconds(baud, bits)
    t3_5 = t3_5_seconds(baud, bits)
    records = []
    noise_from = None

    def flush_noise(upto):
        nonlocal noise_from
        start = noise_from
        for k in range(noise_from + 1, upto + 1):
            if k == upto or ends[k] - ct - ends[k - 1] >= t3_5:
                records.append({"kind": "noise", "t": ends[start] - ct, "hex": buf[start:k].hex()})
                start = k
        noise_from = None

    i = 0
    txn = 0
    open_request = None  # the last frame, when it can be a request still waiting for its answer
    while i < len(buf):
        found = frame_at(buf, i)
        if found is None:
            if noise_from is None:
                noise_from = i
            i += 1
            continue
        if noise_from is not None:
            flush_noise(i)
        length = found
        frame = buf[i:i + length]
        as_request, as_response = fits(buf, i, length)
        rec = {"kind": "frame", "t": ends[i] - ct, "hex": frame.hex(), "txn": None}
        req = open_request
        open_request = None
        if (req is not None and as_response and frame[0] == req["_slave"]
                and frame[1] & 0x7F == req["_fc"]):
            rec["txn"] = req["txn"]
        elif as_request:
            txn += 1
            rec["txn"] = txn
            rec["_slave"], rec["_fc"] = frame[0], frame[1]
            open_request = rec
        records.append(rec)
        i += length
    if noise_from is not None:
        flush_noise(len(buf))
    # A request nobody answered is not part of a pair.
    counts = {}
    for r in records:
        if r.get("txn") is not None:
            counts[r["txn"]] = counts.get(r["txn"], 0) + 1
    for r in records:
        if r.get("txn") is not None and counts[r["txn"]] < 2:
            r["txn"] = None
    return records


def main(argv):
    if len(argv) != 1:
        sys.exit(__doc__)
    baud, bits, buf, ends = read_capture(argv[0])
    out = sys.stdout
    for r in decode(baud, bits, buf, ends):
        clean = {k: v for k, v in r.items() if not k.startswith("_")}
        clean["t"] = round(clean["t"], 9)
        out.write(json.dumps(clean) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
