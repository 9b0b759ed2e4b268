#!/usr/bin/env python3
"""Writes the seed corpus of fuzz_pdu_decode from real frames.

Seeds are the example frames of the four device documents and of MODBUS Application
Protocol V1.1b3 §6 (slave 0x11), in the input layout fuzz_pdu_decode.cpp describes:
mode byte (0 request, 1 response, 2 unknown role, 3 response with its request), then the
frame(s) with their CRC. Files named seed-* are rewritten by this script; files named
regression-* are crashes the fuzzer found and are never touched.

usage: tests/fuzz/make_pdu_seeds.py [OUTPUT_DIR]   (default captures/regressions/fuzz/pdu_decode)
"""
import os
import pathlib
import sys

# tools/pylib (modbus_crc), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from modbus_crc import with_crc  # noqa: E402

REQUEST, RESPONSE, UNKNOWN, PAIR = 0, 1, 2, 3


def adu(hex_text: str) -> bytes:
    """The frame written as hex, with its CRC appended."""
    return with_crc(bytes.fromhex(hex_text))


def as_is(hex_text: str) -> bytes:
    """The frame written as hex, CRC included (kept as documented, even when it is wrong)."""
    return bytes.fromhex(hex_text)


# name: (mode, frame) or (PAIR, request, response)
SEEDS = {
    # devices/YW2050.md
    "yw2050-read-0032": (PAIR, as_is("01 03 00 32 00 03 A4 04"),
                         as_is("01 03 06 EA 60 C3 50 DB 6C D1 3F")),
    "yw2050-write-single": (REQUEST, as_is("01 06 00 02 00 02 A9 CB")),
    "yw2050-write-multiple": (PAIR, as_is("01 10 00 00 00 02 04 00 64 00 00 B2 70"),
                              as_is("01 10 00 00 00 02 41 C8")),
    # devices/YW2300.md
    "yw2300-fc01": (PAIR, as_is("01 01 00 00 00 03 7C 0B"), as_is("01 01 01 03 11 89")),
    "yw2300-fc02": (PAIR, as_is("01 02 00 00 00 07 39 C8"), as_is("01 02 01 1F E0 40")),
    "yw2300-fc05": (RESPONSE, as_is("01 05 00 00 FF 00 8C 3A")),
    "yw2300-fc10": (PAIR, as_is("01 10 54 50 00 02 04 00 01 00 03 29 91"),
                    as_is("01 10 54 50 00 02 51 E9")),
    # devices/TH900.md
    "th900-read-sv": (PAIR, as_is("01 03 00 00 00 02 C4 0B"), as_is("01 03 04 02 BC 00 00 3A 6F")),
    "th900-write-sv": (REQUEST, as_is("01 10 00 00 00 02 04 03 E8 00 00 73 DF")),
    # devices/YAKOTEC.md
    "yakotec-malformed-fc10": (PAIR, as_is(
        "01 10 00 21 00 05 0C 00 0A 00 64 00 64 00 3C 00 00 00 03 E8 04 76"),
        as_is("01 10 00 21 00 05 50 00")),
    "yakotec-bad-crc-exception": (PAIR, as_is("01 03 00 20 00 01 85 C1"), as_is("01 83 01 80 F0")),
    "yakotec-jog": (REQUEST, as_is("01 10 00 1D 00 03 06 00 3C 00 64 00 64 66 DE")),
    # V1.1b3 §6 examples, every public function code
    "fc03-request": (REQUEST, adu("11 03 00 6B 00 03")),
    "fc03-response": (RESPONSE, adu("11 03 06 02 2B 00 00 00 64")),
    "fc04-pair": (PAIR, adu("11 04 00 08 00 01"), adu("11 04 02 00 0A")),
    "fc01-pair": (PAIR, adu("11 01 00 13 00 13"), adu("11 01 03 CD 6B 05")),
    "fc06-unknown-role": (UNKNOWN, adu("11 06 00 01 00 03")),
    "fc07-request": (REQUEST, adu("11 07")),
    "fc07-response": (RESPONSE, adu("11 07 6D")),
    "fc08-pair": (PAIR, adu("11 08 00 00 A5 37"), adu("11 08 00 00 A5 37")),
    "fc08-counter": (PAIR, adu("11 08 00 0B 00 00"), adu("11 08 00 0B 01 2C")),
    "fc0b-pair": (PAIR, adu("11 0B"), adu("11 0B FF FF 01 08")),
    "fc0c-pair": (PAIR, adu("11 0C"), adu("11 0C 08 00 00 01 08 01 21 20 00")),
    "fc0f-pair": (PAIR, adu("11 0F 00 13 00 0A 02 CD 01"), adu("11 0F 00 13 00 0A")),
    "fc11-pair": (PAIR, adu("11 11"), adu("11 11 03 2A FF 01")),
    "fc14-pair": (PAIR, adu("11 14 0E 06 00 04 00 01 00 02 06 00 03 00 09 00 02"),
                  adu("11 14 0C 05 06 0D FE 00 20 05 06 33 CD 00 40")),
    "fc15-pair": (PAIR, adu("11 15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D"),
                  adu("11 15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D")),
    "fc16-pair": (PAIR, adu("11 16 00 04 00 F2 00 25"), adu("11 16 00 04 00 F2 00 25")),
    "fc17-pair": (PAIR, adu("11 17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF"),
                  adu("11 17 0C 00 FE 0A CD 00 01 00 03 00 0D 00 FF")),
    "fc18-pair": (PAIR, adu("11 18 04 DE"), adu("11 18 00 06 00 02 01 B8 12 84")),
    "fc2b-0e-pair": (PAIR, adu("11 2B 0E 01 00"), adu(
        "11 2B 0E 01 01 00 00 03 00 04 41 43 4D 45 01 02 58 31 02 05 56 32 2E 31 31")),
    "fc2b-0e-private-object": (RESPONSE, adu(
        "11 2B 0E 03 83 FF 80 02 00 04 41 43 4D 45 80 02 E9 09")),
    "fc2b-0d": (REQUEST, adu("11 2B 0D 01 02 03")),
    "exception-unknown-role": (UNKNOWN, as_is("01 83 02 C0 F1")),
    "user-function": (REQUEST, adu("01 41 01 02 03")),
    # malformed on purpose
    "truncated-fc03": (REQUEST, adu("11 03 00 6B")),
    "lying-bytecount-fc03": (RESPONSE, adu("11 03 FA 00 01")),
    "lying-objects-fc2b": (RESPONSE, adu("11 2B 0E 01 01 00 00 FF 00 FF 41")),
    "lying-fifo-count": (RESPONSE, adu("11 18 FF FF 00 1F 00 01")),
    "two-bytes": (RESPONSE, as_is("11 03")),
    "broadcast-read": (REQUEST, adu("00 03 00 00 00 01")),
}


def main() -> int:
    root = pathlib.Path(__file__).resolve().parents[2]
    out = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else \
        root / "captures" / "regressions" / "fuzz" / "pdu_decode"
    out.mkdir(parents=True, exist_ok=True)
    for old in out.glob("seed-*"):
        old.unlink()
    for name, seed in SEEDS.items():
        mode = seed[0]
        if mode == PAIR:
            request, response = seed[1], seed[2]
            data = bytes([PAIR, len(request)]) + request + response
        else:
            data = bytes([mode]) + seed[1]
        (out / f"seed-{name}").write_bytes(data)
    print(f"wrote {len(SEEDS)} seeds to {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
