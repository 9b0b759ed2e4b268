#!/usr/bin/env python3
"""Line settings inferred from the byte timing, end to end through the real rtuscope.

- Per-byte simulator captures with their settings line removed, at four rates and three
  character sizes: inferred (8N1 as 8N1; 8E1 and 8N2 as 8E1, by the Modbus rule), said to be
  confident, and decoded exactly as with the right settings given.
- The same through Saleae exports at four rates and all three character sizes.
- Real sigrok captures from other tools, without their settings: the rate and character
  size they were recorded at.
- USB-chunked reads at four rates: nothing is inferred, the message says why, and the
  records are those of the Modbus default (no timing invented).
- --baud auto wins over settings a file declares wrongly; --parity fixes the character size;
  a malformed --baud and --baud auto on a live port are refused.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail, fresh_dir  # noqa: E402  (after the path line)


class Tools:
    def __init__(self, args):
        self.rtuscope = args.rtuscope
        self.rtusim = args.rtusim
        self.work = args.work

    def simulate(self, name, baud, parity, stop, chunking="perbyte", saleae=False):
        out = os.path.join(self.work, f"{name}.hex")
        cmd = [self.rtusim, "--transactions", "150", "--baud", str(baud), "--parity", parity,
               "--stop", str(stop), "--chunking", chunking, "--seed", "7", "--out", out]
        if saleae:
            cmd += ["--saleae", os.path.join(self.work, f"{name}.csv")]
        subprocess.run(cmd, check=True, capture_output=True)
        # Drop the settings line: the capture then declares nothing.
        with open(out) as f:
            lines = [line for line in f if not line.startswith("# baud=")]
        with open(out, "w") as f:
            f.writelines(lines)
        return os.path.join(self.work, f"{name}.csv") if saleae else out

    def decode(self, capture, *options):
        run = subprocess.run([self.rtuscope, "decode", capture, "--format", "jsonl", "-q",
                              *options], capture_output=True, text=True)
        if run.returncode != 0:
            fail(f"decode {capture} {options}: exit {run.returncode}: {run.stderr}")
        lines = run.stdout.splitlines()
        return json.loads(lines[0]), lines[1:], run.stderr


def expect_inferred(tools, capture, baud, bits_label, line, *options):
    header, records, stderr = tools.decode(capture, *options)
    settings = (header["baud"], header["parity"], header["stop_bits"])
    if settings != line:
        fail(f"{capture}: decoded at {settings}, expected {line}")
    notes = [w for w in header["warnings"] if w.startswith("line settings inferred")]
    if len(notes) != 1 or f"{baud} baud at {bits_label}" not in notes[0] \
            or "confident" not in notes[0] or notes[0] not in stderr:
        fail(f"{capture}: inference note {notes}, stderr {stderr!r}")
    return records


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--rtusim", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--work", required=True)
    args = ap.parse_args()
    fresh_dir(args.work)
    tools = Tools(args)

    cases = [(4800, "N", 1, "10 bits", ("N", 1)), (9600, "E", 1, "11 bits", ("E", 1)),
             (38400, "N", 2, "11 bits", ("E", 1)), (115200, "E", 1, "11 bits", ("E", 1))]
    for baud, parity, stop, bits, (got_parity, got_stop) in cases:
        capture = tools.simulate(f"perbyte_{baud}", baud, parity, stop)
        records = expect_inferred(tools, capture, baud, bits, (baud, got_parity, got_stop))
        _, given, _ = tools.decode(capture, "--baud", str(baud), "--parity", got_parity,
                                   "--stop", str(got_stop))
        if records != given:
            fail(f"{capture}: inferred settings decode differently from the same given")
        auto = expect_inferred(tools, capture, baud, bits, (baud, got_parity, got_stop),
                               "--baud", "auto")
        if auto != records:
            fail(f"{capture}: --baud auto differs from inference by default")
        print(f"per byte {baud} 8{parity}{stop}: inferred {baud} 8{got_parity}{got_stop}, "
              f"{len(records)} records as with the settings given")

    for baud, parity, stop, bits, line in ((2400, "E", 1, "11 bits", (2400, "E", 1)),
                                           (19200, "N", 1, "10 bits", (19200, "N", 1)),
                                           (57600, "E", 1, "11 bits", (57600, "E", 1)),
                                           (115200, "N", 2, "11 bits", (115200, "E", 1))):
        capture = tools.simulate(f"saleae_{baud}", baud, parity, stop, saleae=True)
        expect_inferred(tools, capture, baud, bits, line)
        print(f"Saleae export {baud} 8{parity}{stop}: inferred {line}")

    captures = os.path.join(args.source, "captures")
    sigrok = sorted(f for f in os.listdir(captures) if f.startswith("sigrok_") and f.endswith(".csv"))
    for name in sigrok:
        with open(os.path.join(captures, name[:-4] + ".args")) as f:
            given = f.read().split()
        baud = int(given[given.index("--baud") + 1])
        parity = given[given.index("--parity") + 1]
        stop = int(given[given.index("--stop") + 1])
        bits = 9 + (parity != "N") + stop
        line = (baud, "N", 1) if bits == 10 else (baud, "E", 1)
        expect_inferred(tools, os.path.join(captures, name), baud, f"{bits} bits", line)
        print(f"{name} (recorded at {baud} 8{parity}{stop}): inferred {line}")
    if len(sigrok) < 4:
        fail(f"expected the four bundled sigrok captures, found {sigrok}")

    # A USB adapter delivers a latency timer's worth of bytes per read, give or take the
    # host's wake-up: the character time is not in the timestamps, at any rate.
    for baud, parity, stop in ((4800, "N", 1), (9600, "E", 1), (19200, "E", 1), (115200, "N", 2)):
        usb = tools.simulate(f"usb_{baud}", baud, parity, stop, chunking="usb")
        header, records, stderr = tools.decode(usb, "--baud", "auto")
        if header["baud"] != 9600 or "cannot be measured" not in stderr \
                or any(w.startswith("line settings inferred") for w in header["warnings"]) \
                or "assumed" in stderr:
            fail(f"USB capture at {baud} with --baud auto: {header}, {stderr!r}")
        _, default, _ = tools.decode(usb, "--baud", "9600")
        if records != default:
            fail(f"USB capture at {baud}: --baud auto decodes differently from the Modbus default")
        print(f"USB-chunked {baud} 8{parity}{stop}: not inferred, says why, decodes as the "
              "Modbus default")

    wrong = os.path.join(captures, "wrong_baud_19200_as_9600.hex")
    shutil.copy(wrong, os.path.join(args.work, "declared_wrong.hex"))
    declared = os.path.join(args.work, "declared_wrong.hex")
    with open(declared) as f:
        text = f.read().replace("# baud=19200", "# baud=9600", 1)
    with open(declared, "w") as f:
        f.write(text)
    expect_inferred(tools, declared, 19200, "11 bits", (19200, "E", 1), "--baud", "auto")
    header, _, _ = tools.decode(declared)
    if header["baud"] != 9600:
        fail(f"without --baud auto a declared rate must be kept: {header['baud']}")
    odd = tools.simulate("odd_19200", 19200, "O", 1)
    expect_inferred(tools, odd, 19200, "11 bits", (19200, "O", 1), "--baud", "auto",
                    "--parity", "O")
    print("--baud auto wins over a declared rate; --parity O gives 8O1")

    run = subprocess.run([args.rtuscope, "decode", wrong, "--baud", "19k"], capture_output=True,
                         text=True)
    if run.returncode != 2 or "--baud: expected a rate from 50 to 20000000 or 'auto', found '19k'" \
            not in run.stderr:
        fail(f"--baud 19k: exit {run.returncode}: {run.stderr}")
    run = subprocess.run([args.rtuscope, "live", "/dev/null", "--baud", "auto"],
                         capture_output=True, text=True)
    if run.returncode != 2 or "rtuscope probe PORT" not in run.stderr:
        fail(f"live --baud auto: exit {run.returncode}: {run.stderr}")
    print("malformed --baud and live --baud auto are refused")
    return 0


if __name__ == "__main__":
    sys.exit(main())
