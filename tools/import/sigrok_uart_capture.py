#!/usr/bin/env python3
"""Turn a sigrok logic-analyser session (.sr) of a serial line into a capture rtuscope reads.

Why: real captures recorded by other people with other tools (the public sigrok example
dumps) test the decoder on traffic nobody on this project generated. rtuscope does not read
.sr files; this script keeps each imported capture reproducible from its original.

How: sigrok-cli's own UART protocol decoder does the bit-level work. It is run once per
chosen channel (run on two channels at once it labels both "uart-1", so the directions could
not be told apart), with --protocol-decoder-samplenum so that every annotation carries its
sample numbers. From the annotations of each character:
  - start    = first sample of its "Start bit" (the falling edge the decoder synchronised on);
  - value    = the data annotation (hex);
  - error    = "framing" when sigrok reports "Frame error" (stop bit sampled low, as in a
               break or a glitch on an undriven bus), else "parity" on "Parity error";
  - duration = the nominal character time, (1 start + 8 data + parity + stop) bits / baud,
               rounded to the nanosecond. The .sr file has no better end: sigrok's own
               annotations end on whole samples of its rounded bit time.
Characters of all channels are merged in order of their start sample (ties: channel order
on the command line).

For 2 stop bits sigrok is told 1 stop bit: like a UART receiver it then checks only the
first stop bit and may see the next start bit in the second one; the duration still counts
both. sigrok-cli ignores pulses shorter than half a bit (it samples the start bit in its
middle), so very short spikes leave no character; the "Break condition" annotation is not
used (the break's first character is already there, with its framing error).

Output (--format):
  csv  Saleae Logic 2 "data table" layout (name,type,start_time,duration,"data","error"),
       the layout rtuscope reads with per-byte exact timing. The name column is the sigrok
       channel the byte was seen on. Line settings cannot be declared in it: pass them with
       --baud/--parity/--stop (for captures/ the beside-file <name>.args).
  hex  rtuscope text hex, one byte per line stamped with the end of its character
       (start + duration), "# baud=... parity=... stop=..." first. It has no error flags:
       bytes with framing or parity errors are kept and flagged in a trailing comment only.
Times are seconds from the first sample of the session (a .sr file has no wall-clock time).

Needs sigrok-cli on PATH (Debian package sigrok-cli; made with 0.7.2 / libsigrokdecode
0.5.3). Python 3 standard library only.

Example:
  tools/import/sigrok_uart_capture.py wizmodbus.sr --channel BA+ --baud 9600 --parity N \\
      --stop 1 --format csv -o captures/sigrok_wizmodbus_bus.csv
"""
import argparse
import re
import subprocess
import sys
from fractions import Fraction

PARITY_NAMES = {"N": "none", "E": "even", "O": "odd"}
ANNOTATION = re.compile(r"^(\d+)-(\d+) \S+: (.*)$")


def samplerate_of(sr_file):
    """Samples per second of the session, from `sigrok-cli --show`."""
    out = subprocess.run(["sigrok-cli", "-i", sr_file, "--show"], check=True,
                         capture_output=True, text=True).stdout
    m = re.search(r"^Samplerate: (\d+)$", out, re.MULTILINE)
    if not m:
        sys.exit(f"{sr_file}: no 'Samplerate:' in sigrok-cli --show output")
    return int(m.group(1))


def decode_channel(sr_file, channel, baud, parity, invert):
    """Characters on one channel: list of dicts with start sample, value, error."""
    options = [f"baudrate={baud}", f"parity={PARITY_NAMES[parity]}", "stop_bits=1.0",
               "data_bits=8", f"rx={channel}", f"invert_rx={'yes' if invert else 'no'}"]
    cmd = ["sigrok-cli", "-i", sr_file, "-P", "uart:" + ":".join(options),
           "-A", "uart=rx-start:rx-data:rx-parity-err:rx-warnings",
           "--protocol-decoder-samplenum"]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    chars = []
    current = None
    for line in out.splitlines():
        m = ANNOTATION.match(line)
        if not m:
            sys.exit(f"unexpected sigrok-cli output line: {line!r}")
        start, text = int(m.group(1)), m.group(3)
        if text == "Start bit":
            current = {"start": start, "value": None, "error": "", "channel": channel}
            chars.append(current)
        elif re.fullmatch(r"[0-9A-F]{2}", text):
            if current is None or current["value"] is not None:
                sys.exit(f"data without a start bit at sample {start}")
            current["value"] = int(text, 16)
        elif text == "Parity error":
            if current is not None and not current["error"]:
                current["error"] = "parity"
        elif text == "Frame error":
            if current is not None:
                current["error"] = "framing"
        else:
            sys.exit(f"unexpected annotation at sample {start}: {text!r}")
    # A start bit at the very end of the session may have no data annotation.
    return [c for c in chars if c["value"] is not None]


def seconds(fraction):
    """Exact decimal seconds with 9 decimals (samples of 1 MHz and 4 MHz are whole ns)."""
    ns = fraction * 1_000_000_000
    rounded = round(ns)
    whole, rest = divmod(rounded, 1_000_000_000)
    return f"{whole}.{rest:09d}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("sr_file")
    ap.add_argument("--channel", action="append", required=True,
                    help="sigrok channel name (repeat to merge several lines)")
    ap.add_argument("--baud", type=int, required=True)
    ap.add_argument("--parity", choices=sorted(PARITY_NAMES), required=True)
    ap.add_argument("--stop", type=int, choices=(1, 2), required=True)
    ap.add_argument("--invert", action="store_true",
                    help="idle low on the wire as probed (e.g. an RS-232 line)")
    ap.add_argument("--format", choices=("csv", "hex"), required=True)
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args()

    rate = samplerate_of(args.sr_file)
    chars = []
    for order, channel in enumerate(args.channel):
        for c in decode_channel(args.sr_file, channel, args.baud, args.parity, args.invert):
            c["order"] = order
            chars.append(c)
    chars.sort(key=lambda c: (c["start"], c["order"]))

    bits = 1 + 8 + (0 if args.parity == "N" else 1) + args.stop
    duration = Fraction(bits, args.baud)
    with open(args.output, "w", newline="\n") as f:
        if args.format == "csv":
            f.write('name,type,start_time,duration,"data","error"\n')
            for c in chars:
                start = Fraction(c["start"], rate)
                f.write(f'"{c["channel"]}","data",{seconds(start)},{seconds(duration)},'
                        f'0x{c["value"]:02X},{c["error"]}\n')
        else:
            f.write(f"# baud={args.baud} parity={args.parity} stop={args.stop}\n")
            for c in chars:
                end = Fraction(c["start"], rate) + duration
                note = f"  # {c['error']} error" if c["error"] else ""
                f.write(f"{seconds(end)} {c['value']:02X}{note}\n")
    errors = sum(1 for c in chars if c["error"])
    print(f"{args.output}: {len(chars)} bytes, {errors} with errors, "
          f"samplerate {rate} Hz", file=sys.stderr)


if __name__ == "__main__":
    main()
