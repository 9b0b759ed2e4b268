#!/usr/bin/env python3
"""Writes captures/device_examples.hex: every CRC-checked example frame of the four device
documents (../shared/devices/TH900.md, YAKOTEC.md, YW2050.md, YW2300.md) as request/response
exchanges on one 9600 8E1 bus, one byte per line with the time its stop bit ended.

The documents put every example at slave 1. On one bus they would clash, so YAKOTEC keeps
slave 1 (its frames stay byte for byte as documented, including the request with a bad CRC
and the malformed FC10 request) and the others move: TH900 to 2, YW2050 to 3, YW2300 to 4,
with their CRCs recomputed. Timing: bytes of a frame back to back at 11 bits / 9600 baud,
slave latency 5-20 ms from a fixed seed, 50 ms from the end of one transaction to the next
request. Run it again to reproduce the file exactly; never edit the capture by hand.

The same bytes and times are also written as the two Saleae Logic export layouts
(captures/device_examples_saleae_legacy.csv, captures/device_examples_saleae_table.csv), so
that both readers are decoded end to end by the golden tests.

Usage: tools/make_examples_capture.py [OUTPUT_DIR]   (default: captures/)
"""

import os
import random
import sys

# tools/pylib (modbus_crc), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "pylib"))
from modbus_crc import with_crc  # noqa: E402

BAUD = 9600
CHAR_NS = 11 * 1_000_000_000 // BAUD  # 1 145 833 ns: start + 8 data + parity + stop
GAP_BETWEEN_TRANSACTIONS_NS = 50_000_000
LATENCY_RANGE_US = (5_000, 20_000)
START_NS = 1_700_000_000_000_000_000  # any epoch will do; this one reads like a wall clock
SEED = 2050

# (device, slave address on this bus, [(description, request, response)]).
# response "echo" = the request echoed; None = the document shows no response.
# A request marked with bad_crc=True carries the wrong CRC on purpose (kept as documented).
DEVICES = [
    ("TH900", 2, [
        ("read SV (700 = 70.0)", "01 03 00 00 00 02 C4 0B", "01 03 04 02 BC 00 00 3A 6F"),
        ("write SV = 100.0", "01 10 00 00 00 02 04 03 E8 00 00 73 DF", "01 10 00 00 00 02 41 C8"),
        ("write single 0023 = 9 (the seed calls it CYT; its table puts CYT at 2F)",
         "01 06 00 23 00 09 B8 06", "echo"),
        ("generic frame example, no response in the document", "01 03 00 10 00 02 C5 CE", None),
    ]),
    ("YAKOTEC", 1, [
        ("read 0023 (60 r/min)", "01 03 00 23 00 01 75 C0", "01 03 02 00 3C B8 55"),
        ("read 000A..000C", "01 03 00 0A 00 03 25 C9", "01 03 06 00 00 13 88 00 00 A5 DB"),
        ("write 0023 = 60", "01 06 00 23 00 3C 78 11", "echo"),
        ("write 0021 = 500 ms", "01 06 00 21 01 F4 D9 D7", "echo"),
        ("write 0024..0025 = 5000", "01 10 00 24 00 02 04 00 00 13 88 FD 12",
         "01 10 00 24 00 02 01 C3"),
        ("write jog 001D..001F", "01 10 00 1D 00 03 06 00 3C 00 64 00 64 66 DE",
         "01 10 00 1D 00 03 10 0E"),
        ("control 0027 = 0001 (start position move)", "01 06 00 27 00 01 F8 01", "echo"),
        ("control 0027 = 0002 (start jog move)", "01 06 00 27 00 02 B8 00", "echo"),
        ("MALFORMED in the document: quantity 5, byte count 12, 13 data bytes; valid CRC",
         "01 10 00 21 00 05 0C 00 0A 00 64 00 64 00 3C 00 00 00 03 E8 04 76",
         "01 10 00 21 00 05 50 00"),
        ("vendor exception 01: request with a BAD CRC (right one is 85 C0) is answered",
         "01 03 00 20 00 01 85 C1", "01 83 01 80 F0"),
        ("vendor exception 02: unsupported function", "01 02 00 00 00 04 79 C9", "01 82 02 C1 61"),
        ("vendor exception 03: register address out of range", "01 03 00 3C 00 01 44 06",
         "01 83 03 01 31"),
        ("vendor exception 04: write address out of range", "01 06 FF 00 FF FF B8 6E",
         "01 86 04 43 A3"),
        ("vendor exception 05: too many registers", "01 03 00 20 00 20 45 D8", "01 83 05 81 33"),
        ("vendor exception 06: function does not fit the address", "01 06 00 00 00 01 48 0A",
         "01 86 06 C2 62"),
        ("vendor exception 07: value out of range", "01 06 00 20 FF FF 89 B0", "01 86 07 03 A2"),
    ]),
    ("YW2050", 3, [
        ("read 3 from 0032 (byte addressing: 0032, 0034, 0036)", "01 03 00 32 00 03 A4 04",
         "01 03 06 EA 60 C3 50 DB 6C D1 3F"),
        ("write single 0002 (wiring) = 0002", "01 06 00 02 00 02 A9 CB", "echo"),
        ("write multiple 0000, 2 registers (PT = 100)", "01 10 00 00 00 02 04 00 64 00 00 B2 70",
         "01 10 00 00 00 02 41 C8"),
    ]),
    ("YW2300", 4, [
        ("FC01 read 3 outputs", "01 01 00 00 00 03 7C 0B", "01 01 01 03 11 89"),
        ("FC02 read DI1-DI7", "01 02 00 00 00 07 39 C8", "01 02 01 1F E0 40"),
        ("FC03 read 3 from 0106 (IA = IB = IC = 5000)", "01 03 01 06 00 03 E4 36",
         "01 03 06 13 88 13 88 13 88 4A 31"),
        ("FC05 output 1 on", "01 05 00 00 FF 00 8C 3A", "echo"),
        ("FC06 baud = 3", "01 06 54 51 00 03 88 2A", "echo"),
        ("FC10 5450..5451 = 1, 3", "01 10 54 50 00 02 04 00 01 00 03 29 91",
         "01 10 54 50 00 02 51 E9"),
    ]),
]
BAD_CRC_REQUESTS = {"01 03 00 20 00 01 85 C1"}


def frame(text, address, bad_crc_allowed=False):
    """Bytes of a documented frame, CRC checked, moved to `address` with its CRC redone."""
    data = bytes.fromhex(text)
    crc_ok = with_crc(data[:-2]) == data
    if not crc_ok and not bad_crc_allowed:
        sys.exit(f"CRC of documented frame {text} does not check")
    if data[0] == address:
        return data
    if not crc_ok:
        sys.exit(f"cannot move the bad-CRC frame {text} to another address")
    return with_crc(bytes([address]) + data[1:-2])


def fmt_time(ns):
    sign = "-" if ns < 0 else ""
    ns = abs(ns)
    return f"{sign}{ns // 1_000_000_000}.{ns % 1_000_000_000:09d}"


def bus_events():
    """[(label or None, start_ns, byte)]: the whole bus, byte by byte; label on a frame's first
    request byte names the transaction."""
    rng = random.Random(SEED)
    events = []
    t = START_NS  # end of the last byte on the bus

    def emit(data, label=None):
        nonlocal t
        for i, b in enumerate(data):
            events.append((label if i == 0 else None, t, b))
            t += CHAR_NS

    for device, address, examples in DEVICES:
        for description, request_text, response_text in examples:
            request = frame(request_text, address, request_text in BAD_CRC_REQUESTS)
            emit(request, f"{device} @ {address}: {description}")
            if response_text is not None:
                response = request if response_text == "echo" else frame(response_text, address)
                t += rng.randint(*LATENCY_RANGE_US) * 1000
                emit(response)
            t += GAP_BETWEEN_TRANSACTIONS_NS
    return events


HEADER = [
    "Every CRC-checked example frame of the four device documents (TH900, YAKOTEC,",
    "YW2050, YW2300 in ../shared/devices/) as request/response exchanges on one bus.",
    "Written by tools/make_examples_capture.py; regenerate it, never edit it by hand.",
    "baud=9600 parity=E stop=1",
    "One byte per line; the time is when the byte's stop bit ended (11 bits at 9600 baud =",
    "1145.833 us a character), bytes of a frame back to back, slave latency 5-20 ms,",
    "50 ms from the end of one transaction to the next request.",
    "The documents put every example at slave 1. YAKOTEC keeps slave 1, byte for byte as",
    "documented (with its bad-CRC request and its malformed FC10 request); TH900 is moved",
    "to slave 2, YW2050 to 3 and YW2300 to 4, with their CRCs recomputed.",
]


def write_hex(path, events):
    lines = ["# " + h for h in HEADER]
    for label, start, b in events:
        if label:
            lines.append(f"# {label}")
        lines.append(f"{fmt_time(start + CHAR_NS)} {b:02X}")
    return lines


def write_saleae_legacy(path, events):
    """Logic 1.x / legacy export: start-bit times relative to the trigger (set on the first
    byte), 15 decimals as the analyzer writes them."""
    trigger = events[0][1]
    lines = ["Time [s],Value,Parity Error,Framing Error"]
    for _, start, b in events:
        rel = start - trigger
        lines.append(f"{fmt_time(rel)}000000,0x{b:02X},,")
    return lines


def write_saleae_table(path, events):
    """Logic 2 data table export: times relative to the capture start (1 ms before the first
    byte), the duration in e-notation, as Logic 2 writes them."""
    origin = events[0][1] - 1_000_000
    lines = ['name,type,start_time,duration,"data"']
    for _, start, b in events:
        rel = start - origin
        lines.append(f'"Async Serial","data",{fmt_time(rel)},{CHAR_NS / 1e9:.6e},0x{b:02X}')
    return lines


OUTPUTS = [
    ("device_examples.hex", write_hex),
    ("device_examples_saleae_legacy.csv", write_saleae_legacy),
    ("device_examples_saleae_table.csv", write_saleae_table),
]


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "captures")
    events = bus_events()
    for name, writer in OUTPUTS:
        path = os.path.join(out_dir, name)
        with open(path, "w", encoding="ascii", newline="\n") as out:
            out.write("\n".join(writer(path, events)) + "\n")


if __name__ == "__main__":
    main()
