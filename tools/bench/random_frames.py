#!/usr/bin/env python3
"""Adversarial traffic for the speed benchmark: CRC-valid frames with a random slave
(0-255), a random function code (0-255) and 0-60 random data bytes, 5 character times
apart, written as a text hex capture (19200 baud 8E1).

  random_frames.py FRAMES OUT.hex [--per-byte] [--seed N]

--per-byte writes each byte on its own line with its exact end time; otherwise each frame
is one line stamped with its last byte's end time (a read per frame).
"""
import argparse
import os
import random
import sys

# tools/pylib (modbus_crc), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../pylib"))
from modbus_crc import with_crc  # noqa: E402  (after the path line)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("frames", type=int)
    ap.add_argument("out")
    ap.add_argument("--per-byte", action="store_true")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    rng = random.Random(args.seed)
    char_ns = 11 * 1_000_000_000 // 19200
    t = 1_000_000
    with open(args.out, "w", encoding="ascii") as out:
        out.write("# baud=19200 parity=E stop=1\n")
        for _ in range(args.frames):
            body = bytes([rng.randrange(256), rng.randrange(256)]) + rng.randbytes(
                rng.randrange(61))
            frame = with_crc(body)
            if args.per_byte:
                for b in frame:
                    t += char_ns
                    out.write(f"{t // 10**9}.{t % 10**9:09d} {b:02x}\n")
            else:
                t += char_ns * len(frame)
                out.write(f"{t // 10**9}.{t % 10**9:09d} {frame.hex(' ')}\n")
            t += 4 * char_ns
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
