#!/usr/bin/env python3
"""Writes pcap/pcapng files with rtuscope's writers (tshark_fixture_writer) and checks that
the real tshark reads what was written: frames, direction, comments, CRC verdicts, pairing,
broadcast and 4-byte frames, ns/us timestamps, and RTAC serial line events by name."""
import argparse
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tshark_fields import one, run_fields  # noqa: E402

FRAME_FIELDS = ["frame.number", "frame.time_epoch", "frame.comment", "frame.protocols",
                "_ws.col.Protocol", "frame.packet_flags_direction", "frame.p2p_dir",
                "frame.interface_name", "frame.interface_description", "mbrtu.unit_id",
                "modbus.func_code", "modbus.exception_code", "mbrtu.crc16.status",
                "modbus.request_frame", "exported_pdu.prot_name", "data.data"]

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def epoch_ns(text):
    sec, _, frac = text.partition(".")
    return int(sec) * 1_000_000_000 + int((frac + "000000000")[:9])


def check_frames(tshark, path, frames, ns, with_meta):
    rows = run_fields(tshark, path, FRAME_FIELDS)
    name = os.path.basename(path)
    check(len(rows) == len(frames), f"{name}: tshark shows {len(rows)} frames, wrote {len(frames)}")
    for row, f in zip(rows, frames):
        n = f["n"]
        where = f"{name} frame {n}"
        t = epoch_ns(one(row, "frame.time_epoch"))
        want_t = f["t_ns"] if ns else f["t_ns"] // 1000 * 1000
        check(t == want_t, f"{where}: time {t} != {want_t}")
        check(one(row, "exported_pdu.prot_name") == "mbrtu", f"{where}: dissector name")
        adu = bytes.fromhex(f["hex"])
        protocols = one(row, "frame.protocols")
        if f["dissected"]:
            check(protocols == "exported_pdu:mbrtu:modbus", f"{where}: protocols {protocols}")
            check(one(row, "mbrtu.unit_id") == str(adu[0]), f"{where}: unit id")
            check(one(row, "modbus.func_code") == str(adu[1] & 0x7F), f"{where}: function code")
            status = one(row, "mbrtu.crc16.status")
            check(status == ("1" if f["crc_ok"] else "0"), f"{where}: CRC status {status}")
            exc = one(row, "modbus.exception_code")
            want_exc = str(adu[2]) if adu[1] & 0x80 else None
            check(exc == want_exc, f"{where}: exception code {exc} != {want_exc}")
            # tshark pairs ordinary responses (not exceptions) with their request.
            if f["direction"] == "response" and not adu[1] & 0x80 and f["request_n"]:
                req = next(x for x in frames if x["n"] == f["request_n"])
                if req["dissected"]:
                    got = one(row, "modbus.request_frame")
                    check(got == str(f["request_n"]),
                          f"{where}: request frame {got} != {f['request_n']}")
        else:
            # mbrtu declines unit 0 and frames under 5 bytes: still a packet, shown as data.
            check(protocols == "exported_pdu:data", f"{where}: protocols {protocols}")
            check(one(row, "data.data") == f["hex"], f"{where}: data {one(row, 'data.data')}")
            if with_meta:
                check(one(row, "_ws.col.Protocol") == "Modbus RTU", f"{where}: protocol column")
        if with_meta:
            comment = one(row, "frame.comment") or ""
            check(comment == f["comment"], f"{where}: comment {comment!r} != {f['comment']!r}")
            want_dir = "0x00000002" if f["direction"] == "request" else "0x00000001"
            check(one(row, "frame.packet_flags_direction") == want_dir, f"{where}: epb_flags")
            check(one(row, "frame.p2p_dir") == ("0" if f["direction"] == "request" else "1"),
                  f"{where}: p2p_dir")
            check(one(row, "frame.interface_name") == "/dev/ttyUSB0", f"{where}: if_name")
            check(one(row, "frame.interface_description") == "RS-485 9600 8E1",
                  f"{where}: if_description")
    return len(rows)


def check_mixed(tshark, path, frames, events):
    rows = run_fields(tshark, path, ["frame.number", "frame.interface_id", "frame.time_epoch",
                                     "rtacser.eventtype", "rtacser.timestamp", "data.data",
                                     "_ws.col.Info", "mbrtu.unit_id", "frame.comment"])
    raw = [r for r in rows if one(r, "frame.interface_id") == "1"]
    decoded = [r for r in rows if one(r, "frame.interface_id") == "0"]
    check(len(raw) == len(events), f"mixed: {len(raw)} raw records, wrote {len(events)}")
    check(len(decoded) == min(len(frames), len(events)), "mixed: decoded frame count")
    for row, e in zip(raw, events):
        where = f"mixed event {e['n']}"
        check(one(row, "rtacser.eventtype") == f"0x{e['event']:02x}", f"{where}: event type")
        info = one(row, "_ws.col.Info") or ""
        check(info.split(" ")[0] == e["name"], f"{where}: info {info!r} does not name {e['name']}")
        check((one(row, "data.data") or "") == e["hex"], f"{where}: payload")
        t = epoch_ns(one(row, "frame.time_epoch"))
        check(t == e["t_ns"] // 1000 * 1000, f"{where}: time {t}")
        if e["name"] != "DATA_RX_START":
            check(one(row, "frame.comment") == "line event", f"{where}: comment")
    for row, f in zip(decoded, frames):
        check(one(row, "mbrtu.unit_id") == (str(bytes.fromhex(f["hex"])[0]) if f["dissected"] else None),
              f"mixed frame {f['n']}: unit id")
    return len(raw), len(decoded)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tshark", required=True)
    ap.add_argument("--writer", required=True)
    ap.add_argument("--workdir", required=True)
    args = ap.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    subprocess.run([args.writer, args.workdir], check=True)
    expected = [json.loads(l) for l in open(os.path.join(args.workdir, "expected.jsonl"))]
    frames = [e for e in expected if e["kind"] == "frame"]
    events = [e for e in expected if e["kind"] == "event"]
    # The fixtures must cover what the checks are about.
    assert any(not f["crc_ok"] for f in frames) and any(not f["dissected"] for f in frames)
    assert any(bytes.fromhex(f["hex"])[1] & 0x80 for f in frames)

    n = check_frames(args.tshark, os.path.join(args.workdir, "frames.pcapng"), frames, True, True)
    n += check_frames(args.tshark, os.path.join(args.workdir, "frames_ns.pcap"), frames, True, False)
    n += check_frames(args.tshark, os.path.join(args.workdir, "frames_us_be.pcap"), frames, False,
                      False)
    raw, decoded = check_mixed(args.tshark, os.path.join(args.workdir, "mixed.pcapng"), frames,
                               events)
    for f in failures:
        print("FAIL:", f)
    print(f"tshark agreed on {n} frames in 3 files and {raw} raw events + {decoded} frames in the "
          f"mixed file; {len(failures)} disagreement(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
