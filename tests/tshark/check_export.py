#!/usr/bin/env python3
"""`rtuscope export` checked against the real tshark, and export -> import round trips.

For each capture (the device examples, simulator traffic with faults in both chunkings, and a
Saleae export with parity/framing errors):
  * every record rtuscope decoded (`decode --format jsonl`) is one packet of the export, in
    order, at the same nanosecond, with a comment that lists its issues;
  * where tshark dissects a frame as Modbus RTU, it reads the same unit id, function code,
    query/response role, exception code, CRC verdict, reference numbers, counts, register
    and coil values; a frame tshark finds malformed must be one rtuscope flagged;
  * tshark pairs responses with the requests rtuscope paired them with;
  * the raw interface holds exactly the input bytes, and its line events (PARITY_ERROR ...)
    fall on the records rtuscope flagged (line_error, break, overrun);
  * decoding the export gives back rtuscope's first decode (exactly with --raw; frames-only
    files estimate frame ends, so t_end/gap/latency are left out there).
Any disagreement fails the test.
"""
import argparse
import decimal
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tshark_fields import one, run_fields  # noqa: E402

FIELDS = ["frame.number", "frame.interface_id", "frame.time_epoch", "frame.comment",
          "frame.protocols", "_ws.col.Info", "_ws.malformed", "mbrtu.unit_id", "modbus.func_code",
          "modbus.exception_code", "mbrtu.crc16.status", "modbus.request_frame",
          "modbus.reference_num", "modbus.word_cnt", "modbus.bit_cnt", "modbus.byte_cnt",
          "modbus.regnum16", "modbus.regval_uint16", "modbus.bitval", "modbus.data",
          "data.data", "rtacser.eventtype"]
PAIRING_ISSUES = {"unsolicited", "late", "wrong_slave", "wrong_function", "timeout"}
DAMAGE_ISSUES = {"crc", "truncated", "bytecount", "too_long", "line_error", "break", "overrun",
                 "address_mismatch", "echo_mismatch", "quantity", "value"}
EVENT_ISSUE = {0x07: "line_error", 0x08: "line_error", 0x09: "break", 0x0A: "overrun"}


class Checker:
    def __init__(self, known):
        self.failures = []
        self.stats = {}
        self.known = known  # {(scenario, hex): reason} of disagreements already understood
        self.known_seen = set()
        self.scenario = ""

    def disagree(self, cond, what, rec):
        """A check between rtuscope and tshark; listed known disagreements are reported,
        not failed, and a listed one that no longer happens fails (keep the list true)."""
        if cond:
            return True
        key = (self.scenario, rec["hex"])
        if key in self.known:
            self.known_seen.add(key)
            print(f"KNOWN: {what} -- {self.known[key]}")
            self.count("known disagreements (listed in known_disagreements.txt)")
            return False
        self.failures.append(what)
        return False

    def check(self, cond, what):
        if not cond:
            self.failures.append(what)
        return cond

    def count(self, key, n=1):
        self.stats[key] = self.stats.get(key, 0) + n


def run(cmd, **kw):
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False, **kw)
    if proc.returncode != 0:
        raise AssertionError(f"{' '.join(cmd)} exited {proc.returncode}: {proc.stderr}")
    return proc.stdout


def decode(rtuscope, path, extra=()):
    lines = run([rtuscope, "decode", path, "--format", "jsonl", *extra]).splitlines()
    # Decimal keeps the nanosecond digits of times exact.
    records = [json.loads(l, parse_float=decimal.Decimal) for l in lines]
    return records[0], records[1:]


def epoch_ns(text):
    sec, _, frac = text.partition(".")
    return int(sec) * 1_000_000_000 + int((frac + "000000000")[:9])


def json_ns(t):
    # JSONL times are decimal seconds with 9 digits: parse the text form, not a float.
    return epoch_ns(format(t, "f"))


def be16(b, i):
    return b[i] << 8 | b[i + 1]


def ints(row, field):
    return [int(v, 0) for v in row[field]]


def expected_fields(rec, request):
    """What tshark should show for a frame, derived from the bytes rtuscope framed and the
    role and request it decided. Only fields whose bytes are all there."""
    b = bytes.fromhex(rec["hex"])
    fc = b[1]
    role = rec["role"]
    n = len(b) - 2  # without CRC
    exp = {}
    if fc & 0x80:
        exp["modbus.exception_code"] = [b[2]]
        return exp
    if role == "request":
        if fc in (1, 2, 15) and n >= 6:
            exp["modbus.reference_num"] = [be16(b, 2)]
            exp["modbus.bit_cnt"] = [be16(b, 4)]
        elif fc in (3, 4, 16) and n >= 6:
            exp["modbus.reference_num"] = [be16(b, 2)]
            exp["modbus.word_cnt"] = [be16(b, 4)]
        elif fc in (5, 6, 22) and n >= 4:
            exp["modbus.reference_num"] = [be16(b, 2)]
        if fc == 16 and n >= 7 and n == 7 + b[6]:
            values = [be16(b, 7 + 2 * i) for i in range(b[6] // 2)]
            exp["modbus.regval_uint16"] = values
            exp["modbus.regnum16"] = [be16(b, 2) + i for i in range(len(values))]
        if fc == 6 and n >= 6:
            exp["modbus.data"] = [b[4:6].hex()]
    elif role == "response":
        if fc in (3, 4) and n >= 3 and n == 3 + b[2]:
            values = [be16(b, 3 + 2 * i) for i in range(b[2] // 2)]
            exp["modbus.regval_uint16"] = values
            if request is not None:
                rq = bytes.fromhex(request["hex"])
                exp["modbus.regnum16"] = [be16(rq, 2) + i for i in range(len(values))]
        elif fc in (1, 2) and n >= 3 and n == 3 + b[2] and request is not None:
            rq = bytes.fromhex(request["hex"])
            quantity = be16(rq, 4)
            bits = [(b[3 + i // 8] >> (i % 8)) & 1 for i in range(8 * b[2])][:quantity]
            exp["modbus.bitval"] = bits
        elif fc in (5, 6, 15, 16) and n >= 6:
            exp["modbus.reference_num"] = [be16(b, 2)]
            if fc == 15:
                exp["modbus.bit_cnt"] = [be16(b, 4)]
            if fc == 16:
                exp["modbus.word_cnt"] = [be16(b, 4)]
            if fc == 6:
                exp["modbus.data"] = [b[4:6].hex()]
    return exp


def check_frames(c, name, records, frame_rows, number_of):
    requests_by_txn = {}
    for rec in records:
        if rec["kind"] == "frame" and rec["role"] == "request" and rec.get("txn") is not None:
            requests_by_txn[rec["txn"]] = rec
    c.check(len(frame_rows) == len(records),
            f"{name}: export holds {len(frame_rows)} packets, decode gave {len(records)} records")
    for i, (rec, row) in enumerate(zip(records, frame_rows)):
        where = f"{name} record {i + 1} (frame {one(row, 'frame.number')}, {rec['hex'][:16]})"
        issues = set(rec.get("issues", []))
        c.check(epoch_ns(one(row, "frame.time_epoch")) == json_ns(rec["t"]), f"{where}: time")
        comment = one(row, "frame.comment") or ""
        for key in issues:
            c.check(f"{key}: " in comment, f"{where}: comment {comment!r} lacks issue {key}")
        b = bytes.fromhex(rec["hex"])
        protocols = one(row, "frame.protocols") or ""
        if rec["kind"] == "noise" or b[0] == 0 or len(b) < 5:
            # Not for mbrtu: shown as data, with the bytes as they are.
            c.check(protocols == "exported_pdu:data", f"{where}: protocols {protocols}")
            c.check(one(row, "data.data") == rec["hex"], f"{where}: data bytes")
            if rec["kind"] == "frame":
                c.check(comment != "", f"{where}: undissected frame without a comment")
            c.count("shown as data (noise, unit 0, < 5 bytes)")
            continue
        c.count("dissected by mbrtu")
        c.check(protocols.startswith("exported_pdu:mbrtu"), f"{where}: protocols {protocols}")
        c.check(one(row, "mbrtu.unit_id") == str(rec["slave"]), f"{where}: unit id")
        status = one(row, "mbrtu.crc16.status")
        fc_values = row["modbus.func_code"]
        # tshark cuts the ADU where the function code's length rule says it ends; when that
        # differs from the frame, it shows a malformed packet and no CRC verdict.
        malformed = bool(row["_ws.malformed"]) or "BoundError" in (one(row, "_ws.col.Info") or "") \
            or not fc_values or status is None
        if malformed:
            c.disagree(issues & DAMAGE_ISSUES,
                       f"{where}: tshark finds it malformed, rtuscope flagged nothing ({issues})",
                       rec)
            c.count("malformed for tshark, flagged by rtuscope")
            continue
        c.disagree(status == ("1" if rec["crc_ok"] else "0"),
                   f"{where}: CRC status {status} but rtuscope crc_ok={rec['crc_ok']}", rec)
        c.check(fc_values == [str(rec["fc"] & 0x7F)], f"{where}: function code {fc_values}")
        info = (one(row, "_ws.col.Info") or "").strip()
        if rec["role"] in ("request", "response"):
            want = "Query" if rec["role"] == "request" else "Response"
            c.check(info.startswith(want), f"{where}: tshark says {info[:20]!r}, rtuscope "
                    f"{rec['role']}")
        request = requests_by_txn.get(rec.get("txn")) if rec["role"] == "response" else None
        # Register numbers and coil counts of a response come from its request: compare them
        # where tshark found the same request (pairing itself is checked below).
        same_request = request is not None and \
            one(row, "modbus.request_frame") == str(number_of.get(id(request)))
        for field, values in expected_fields(rec, request if same_request else None).items():
            got = row[field]
            if field == "modbus.data":
                ok = got == values
            else:
                ok = [int(v, 0) for v in got] == values
            c.check(ok, f"{where}: {field} tshark {got} rtuscope {values}")
            c.count("field values compared")
        # Pairing. tshark pairs an ordinary (non-exception) response with the latest earlier
        # request of the same unit and function; it ignores timeouts.
        if rec["role"] == "response" and not rec["fc"] & 0x80:
            got = one(row, "modbus.request_frame")
            if request is not None:
                rq_bytes = bytes.fromhex(request["hex"])
                if rq_bytes[0] != 0 and len(rq_bytes) >= 5:
                    want = str(number_of[id(request)])
                    if c.check(got == want or issues & PAIRING_ISSUES,
                               f"{where}: tshark pairs it with frame {got}, rtuscope with {want}"):
                        c.count("pairs agreed" if got == want else "pairs differing, flagged")
            elif got is not None:
                c.check(issues & PAIRING_ISSUES,
                        f"{where}: tshark pairs it with frame {got}, rtuscope found no request "
                        f"and flagged nothing")
                c.count("unpaired by rtuscope, paired by tshark, flagged")
            else:
                c.count("unpaired by both")


def check_raw(c, name, records, raw_rows):
    stream = bytearray()
    owner = []  # record index of every byte
    for i, rec in enumerate(records):
        b = bytes.fromhex(rec["hex"])
        stream += b
        owner += [i] * len(b)
    raw = bytearray()
    flagged = {}  # record index -> set of issue keys seen on its bytes
    for row in raw_rows:
        payload = bytes.fromhex(one(row, "data.data") or "")
        event = int(one(row, "rtacser.eventtype"), 16)
        info = one(row, "_ws.col.Info") or ""
        names = {2: "DATA_RX_START", 7: "FRAMING_ERROR", 8: "PARITY_ERROR",
                 9: "SERIAL_BREAK_EVENT", 10: "SERIAL_OVERFLOW_EVENT"}
        c.check(info.split(" ")[0] == names.get(event), f"{name}: raw event {event}: info {info!r}")
        if event in EVENT_ISSUE:
            c.count(f"raw {names[event]} events")
            for k in range(len(raw), len(raw) + len(payload)):
                if k < len(owner):
                    flagged.setdefault(owner[k], set()).add(EVENT_ISSUE[event])
        raw += payload
    c.check(bytes(raw) == bytes(stream),
            f"{name}: raw bytes ({len(raw)}) differ from the decoded records' bytes ({len(stream)})")
    c.count("raw bytes compared", len(raw))
    for i, rec in enumerate(records):
        want = set(rec.get("issues", [])) & set(EVENT_ISSUE.values())
        got = flagged.get(i, set())
        c.check(want == got, f"{name} record {i + 1}: line events on its bytes {got}, issues {want}")


def without_issues(records, keys):
    return [dict(r, issues=[i for i in r.get("issues", []) if i not in keys]) for r in records]


def strip(records, keys):
    return [{k: v for k, v in r.items() if k not in keys} for r in records]


def check_round_trip(c, name, original, again, keys_estimated):
    c.check(len(original) == len(again), f"{name}: round trip gave {len(again)} records, "
            f"not {len(original)}")
    a = strip(original, keys_estimated)
    b = strip(again, keys_estimated)
    for i, (x, y) in enumerate(zip(a, b)):
        if not c.check(x == y, f"{name}: round trip record {i + 1}: {x} != {y}"):
            break
    c.count("records round-tripped", len(original))


def scenario(c, args, name, capture, decode_args=()):
    c.scenario = name
    work = os.path.join(args.workdir, name)
    os.makedirs(work, exist_ok=True)
    header, records = decode(args.rtuscope, capture, decode_args)
    out = os.path.join(work, name + ".pcapng")
    run([args.rtuscope, "export", capture, "-o", out, "--raw", *decode_args])
    rows = run_fields(args.tshark, out, FIELDS)
    frame_rows = [r for r in rows if one(r, "frame.interface_id") == "0"]
    raw_rows = [r for r in rows if one(r, "frame.interface_id") == "1"]
    number_of = {id(rec): int(one(row, "frame.number")) for rec, row in zip(records, frame_rows)}
    check_frames(c, name, records, frame_rows, number_of)
    check_raw(c, name, records, raw_rows)
    c.count("frames compared with tshark", sum(1 for r in records if r["kind"] == "frame"))
    # Round trips: the raw export re-frames to the very same records.
    _, again = decode(args.rtuscope, out, decode_args)
    check_round_trip(c, name + " (pcapng --raw)", records, again, set())
    frames_only = os.path.join(work, name + "_frames.pcapng")
    run([args.rtuscope, "export", capture, "-o", frames_only, *decode_args])
    _, again = decode(args.rtuscope, frames_only, decode_args)
    # Frame records hold each frame's start and bytes, not the silences inside it nor line
    # errors: frame ends are estimated, and timing and line-error issues need the raw interface.
    estimated = {"t_end", "gap_ms", "latency_ms"}
    only_raw = {"t1.5", "t3.5", "line_error", "break", "overrun"}
    records_wo = [dict(r, issues=[i for i in r.get("issues", []) if i not in only_raw])
                  for r in records]
    check_round_trip(c, name + " (pcapng)", records_wo, without_issues(again, only_raw), estimated)
    classic = os.path.join(work, name + ".pcap")
    run([args.rtuscope, "export", capture, "-o", classic, *decode_args])
    _, again = decode(args.rtuscope, classic,
                      ["--baud", str(header["baud"]), "--parity", header["parity"],
                       "--resolution-ms", str(header["timing_resolution_ms"]), *decode_args])
    check_round_trip(c, name + " (pcap)", records_wo, without_issues(again, only_raw), estimated)


def saleae_with_line_errors(source, target):
    """The device examples as a Saleae legacy export with a parity error, a framing error
    and both on some bytes (the simulator writes no line errors)."""
    with open(source) as f:
        lines = f.read().splitlines()
    out = [lines[0]]
    for i, line in enumerate(lines[1:]):
        t, value = line.split(",")[:2]
        parity = "Error" if i in (5, 40, 41, 200) else ""
        framing = "Error" if i in (41, 120) else ""
        out.append(f"{t},{value},{parity},{framing}")
    with open(target, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tshark", required=True)
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--rtusim", required=True)
    ap.add_argument("--source-dir", required=True)
    ap.add_argument("--workdir", required=True)
    args = ap.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    known = {}
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)),
                           "known_disagreements.txt")) as f:
        for line in f:
            line = line.strip()
            if line and not line.startswith("#"):
                name, hexes, reason = line.split(None, 2)
                known[(name, hexes)] = reason
    c = Checker(known)

    scenario(c, args, "device_examples",
             os.path.join(args.source_dir, "captures", "device_examples.hex"))
    for name, sim in [("sim_usb_faults", ["--seed", "11", "--baud", "9600", "--chunking", "usb"]),
                      ("sim_perbyte_faults", ["--seed", "12", "--baud", "19200",
                                              "--chunking", "perbyte"])]:
        capture = os.path.join(args.workdir, name + ".hex")
        run([args.rtusim, *sim, "--transactions", "400", "--faults", "0.1", "--out", capture,
             "--truth", os.path.join(args.workdir, name + ".truth.jsonl")])
        scenario(c, args, name, capture)
    saleae = os.path.join(args.workdir, "line_errors.csv")
    saleae_with_line_errors(
        os.path.join(args.source_dir, "captures", "device_examples_saleae_legacy.csv"), saleae)
    scenario(c, args, "line_errors", saleae)

    # A damaged export: decode keeps every record before the damage, then names the offset.
    whole = os.path.join(args.workdir, "device_examples", "device_examples_frames.pcapng")
    cut = os.path.join(args.workdir, "cut.pcapng")
    with open(whole, "rb") as f:
        data = f.read()
    with open(cut, "wb") as f:
        f.write(data[: len(data) * 2 // 3])
    _, full = decode(args.rtuscope, whole)
    proc = subprocess.run([args.rtuscope, "decode", cut, "--format", "jsonl"],
                          capture_output=True, text=True, check=False)
    part = [json.loads(l, parse_float=decimal.Decimal) for l in proc.stdout.splitlines()][1:]
    c.check(proc.returncode == 2, f"damaged file: exit {proc.returncode}, expected 2")
    c.check(f"cut.pcapng: offset " in proc.stderr and "cut off" in proc.stderr,
            f"damaged file: message {proc.stderr!r}")
    c.check(0 < len(part) < len(full), f"damaged file: {len(part)} of {len(full)} records kept")
    estimated = {"t_end", "gap_ms", "latency_ms", "issues", "txn", "role"}
    c.check(strip(part[:-1], estimated) == strip(full[: len(part) - 1], estimated),
            "damaged file: the records before the damage differ")
    c.count("records kept before damage", len(part))

    for key in sorted(set(known) - c.known_seen):
        c.failures.append(f"listed as a known disagreement but agreed now: {key}; remove it "
                          "from known_disagreements.txt")
    for f in c.failures[:60]:
        print("FAIL:", f)
    if len(c.failures) > 60:
        print(f"... and {len(c.failures) - 60} more")
    for key in sorted(c.stats):
        print(f"{key}: {c.stats[key]}")
    print(f"{len(c.failures)} disagreement(s)")
    return 1 if c.failures else 0


if __name__ == "__main__":
    sys.exit(main())
