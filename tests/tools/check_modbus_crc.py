#!/usr/bin/env python3
"""Checks tools/pylib/modbus_crc.py against frames whose CRC the device documents verify.

The frames are copied from ../shared/devices/*.md (their "Seed examples" sections, CRCs
marked verified there), so the helper is held to real devices rather than to itself.

  check_modbus_crc.py
"""
import os
import sys

# tools/pylib (modbus_crc), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from modbus_crc import crc16, with_crc  # noqa: E402

# (document, frame as documented, CRC included)
DOCUMENTED = [
    ("TH900.md, read SV request", "01 03 00 00 00 02 C4 0B"),
    ("YW2050.md, read 3 from 0032 response", "01 03 06 EA 60 C3 50 DB 6C D1 3F"),
    ("YW2300.md, FC05 output 1 on", "01 05 00 00 FF 00 8C 3A"),
]
# YAKOTEC.md, exception 01: a request sent with a bad CRC; "right one is 85 C0".
BAD = "01 03 00 20 00 01 85 C1"

failures = []


def expect(cond, msg):
    if not cond:
        failures.append(msg)


for where, text in DOCUMENTED:
    frame = bytes.fromhex(text)
    body, low, high = frame[:-2], frame[-2], frame[-1]
    expect(crc16(body) == low | high << 8, f"{where}: crc16 of the body is not {text[-5:]}")
    expect(with_crc(body) == frame, f"{where}: with_crc does not rebuild {text}")
    expect(crc16(frame) == 0, f"{where}: crc16 over the whole frame is not 0")
    # The forms callers use: a list of ints (live tests), a CRC continued (ref_decoder).
    expect(with_crc(list(body)) == frame, f"{where}: with_crc of a list of ints")
    expect(crc16(frame[3:], crc16(frame[:3])) == 0, f"{where}: continued crc16 differs")

bad = bytes.fromhex(BAD)
expect(crc16(bad) != 0, "YAKOTEC.md bad-CRC request passes the check")
expect(with_crc(bad[:-2])[-2:] == bytes.fromhex("85 C0"), "YAKOTEC.md: right CRC is not 85 C0")

for f in failures:
    print(f"FAIL: {f}")
if failures:
    sys.exit(1)
print(f"OK: {len(DOCUMENTED)} documented frames and one documented bad CRC")
