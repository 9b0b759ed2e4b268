#!/usr/bin/env python3
"""Checks of the traffic simulator (rtusim) and the accuracy scorer, run by CTest.

  check_sim.py RTUSIM WORKDIR CHECK [RTUSCOPE [SOURCE_DIR]]

CHECK is one of: determinism, truth, chunking, faults, scorer, heavy (rtusim, the scorer and
the miss classifier alone); decode_clean (RTUSCOPE decodes a fresh clean per-byte capture
perfectly); decode_bytes (every byte accounted for under heavy faults); decode_heavy
(rtuscope and the reference decoder on the heavy profile); decode_recording (the
--pcapng recording decodes as the text hex of the same reads); captures (each
simulated capture in SOURCE_DIR/captures is reproduced by its provenance command and decoded
accurately).
"""
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools", "accuracy"))
# tools/pylib (modbus_crc), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools", "pylib"))
from check_support import fail  # noqa: E402  (after the path line)
import misses  # noqa: E402
import ref_decoder  # noqa: E402
import score  # noqa: E402
from modbus_crc import crc16  # noqa: E402  (the CRC value: 0 over an intact frame)


def expect(cond, msg):
    if not cond:
        fail(msg)


class Sim:
    def __init__(self, exe, work):
        self.exe = os.path.abspath(exe)
        self.work = work
        os.makedirs(work, exist_ok=True)

    def run(self, name, *args):
        """Runs rtusim writing NAME.hex, NAME.truth.jsonl, NAME.csv; returns their paths."""
        paths = {k: os.path.join(self.work, name + ext)
                 for k, ext in (("hex", ".hex"), ("truth", ".truth.jsonl"), ("csv", ".csv"))}
        cmd = [self.exe, *args, "--out", paths["hex"], "--truth", paths["truth"],
               "--saleae", paths["csv"]]
        subprocess.run(cmd, check=True)
        return paths


def read_hex(path):
    """(settings comment, [(t_ns, bytes)]) of a text hex capture."""
    settings = None
    chunks = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if line.startswith("#"):
                if "baud=" in line and settings is None:
                    settings = line
                continue
            t, *hexes = line.split()
            sec, frac = t.split(".")
            expect(len(frac) == 9, f"{path}: time {t} does not have 9 decimals")
            chunks.append((int(sec) * 10**9 + int(frac), bytes.fromhex("".join(hexes))))
    return settings, chunks


def read_truth(path):
    with open(path) as f:
        lines = [json.loads(x) for x in f if x.strip()]
    expect(lines and lines[0]["kind"] == "capture", f"{path}: first line is not the capture header")
    return lines[0], lines[1:]


def ns(text):
    sec, frac = f"{text:.9f}".split(".") if isinstance(text, float) else str(text).split(".")
    return int(sec) * 10**9 + int(frac)


def read_csv_bytes(path):
    out = []
    with open(path) as f:
        header = f.readline().strip()
        expect(header == 'name,type,start_time,duration,"data"', f"{path}: header {header}")
        for line in f:
            name, kind, start, dur, data = line.strip().split(",")
            expect(name == '"Async Serial"' and kind == '"data"', f"{path}: row {line}")
            out.append((ns(start), ns(dur), int(data, 16)))
    return out


def raw_truth_times(path):
    """t/t_end of each truth record exactly as written (no float rounding)."""
    out = []
    with open(path) as f:
        for line in f:
            r = json.loads(line, parse_float=lambda s: s)
            if r["kind"] in ("frame", "noise"):
                out.append((ns(r["t"]), ns(r["t_end"])))
    return out


def check_determinism(sim):
    args = ["--seed", "7", "--transactions", "300", "--faults", "0.2", "--chunking", "usb"]
    a = sim.run("det_a", *args)
    b = sim.run("det_b", *args)
    for k in a:
        da = open(a[k], "rb").read().replace(b"det_a", b"det_x")
        db = open(b[k], "rb").read().replace(b"det_b", b"det_x")
        expect(da == db, f"same seed gave different {k} files")
    c = sim.run("det_c", "--seed", "8", *args[2:])
    expect(open(c["truth"]).read().split("\n", 1)[1] != open(a["truth"]).read().split("\n", 1)[1],
           "another seed gave the same truth")


def check_truth(sim):
    for baud, parity, stop, bits in (("9600", "E", "1", 11), ("19200", "N", "2", 11),
                                     ("115200", "N", "1", 10), ("38400", "O", "1", 11)):
        p = sim.run(f"truth_{baud}", "--seed", "11", "--transactions", "400", "--faults", "0.3",
                    "--baud", baud, "--parity", parity, "--stop", stop)
        header, recs = read_truth(p["truth"])
        expect(header["bits_per_char"] == bits, f"{baud}: bits_per_char {header['bits_per_char']}")
        settings, chunks = read_hex(p["hex"])
        expect(settings == f"# baud={baud} parity={parity} stop={stop}", f"settings line {settings}")
        stream = b"".join(c for _, c in chunks)
        truth_stream = b"".join(bytes.fromhex(r["hex"]) for r in recs)
        expect(stream == truth_stream, f"{baud}: capture bytes differ from the truth's")
        expect(header["bytes"] == len(stream) and header["records"] == len(recs), "header counts")
        char_ns = bits * 10**9 // int(baud)
        times = raw_truth_times(p["truth"])
        saleae = read_csv_bytes(p["csv"])
        expect([v for _, _, v in saleae] == list(stream), "Saleae bytes differ from the capture's")
        i = 0
        prev_end = None
        for r, (t0, t1) in zip(recs, times):
            data = bytes.fromhex(r["hex"])
            expect(len(data) > 0, "empty record")
            # Every byte's exact timing agrees in the per-byte capture, the CSV and the truth.
            expect(saleae[i][0] == t0, f"record at {r['t']}: CSV start {saleae[i][0]} != {t0}")
            expect(chunks[i + len(data) - 1][0] == t1, f"record at {r['t']}: end time differs")
            for k in range(len(data)):
                expect(saleae[i + k][1] == char_ns, "byte duration is not one character time")
                expect(chunks[i + k][0] == saleae[i + k][0] + char_ns, "per-byte time != byte end")
            expect(prev_end is None or t0 >= prev_end, f"records overlap at {r['t']}")
            prev_end = t1
            i += len(data)
            if r["kind"] != "frame":
                continue
            faults = set(r["faults"])
            crc_ok = len(data) >= 4 and crc16(data) == 0
            if "truncated" in faults:
                continue
            if "crc" in faults:
                expect(not crc_ok, f"frame with fault crc has a valid CRC: {r['hex']}")
            else:
                expect(crc_ok, f"frame without fault crc has a bad CRC: {r['hex']}")
            expect(r["slave"] == data[0] and r["fc"] == data[1], "slave/fc differ from the bytes")


def check_chunking(sim):
    for baud in ("9600", "115200"):
        common = ["--seed", "21", "--transactions", "500", "--faults", "0.1", "--baud", baud]
        per = sim.run(f"chunk_per_{baud}", *common, "--chunking", "perbyte")
        usb = sim.run(f"chunk_usb_{baud}", *common, "--chunking", "usb")
        _, pchunks = read_hex(per["hex"])
        _, uchunks = read_hex(usb["hex"])
        expect(all(len(c) == 1 for _, c in pchunks), "per-byte capture has a multi-byte line")
        pstream = b"".join(c for _, c in pchunks)
        ustream = b"".join(c for _, c in uchunks)
        expect(pstream == ustream, f"{baud}: per-byte and USB captures carry different bytes")
        expect(len(uchunks) < len(pchunks) / 2, f"{baud}: USB model hardly batches anything")
        expect(max(len(c) for _, c in uchunks) > 1, "no multi-byte USB chunk")
        i = 0
        prev = None
        for t, c in uchunks:
            expect(prev is None or t > prev, f"USB timestamps go backwards at {t}")
            last_byte_end = pchunks[i + len(c) - 1][0]
            expect(t >= last_byte_end, f"USB chunk at {t} precedes its last byte's end {last_byte_end}")
            i += len(c)
            prev = t
    # An adapter that sends once the line is idle: with no jitter, every read ends at a byte
    # the wire shows followed by that much silence, or as a full packet, and holds no such
    # silence inside.
    idle_ns = 4 * 11 * 10**9 // 19200
    per = sim.run("chunk_idle_per", "--seed", "5", "--transactions", "300", "--faults", "0.1",
                  "--baud", "19200", "--chunking", "perbyte")
    idle = sim.run("chunk_idle", "--seed", "5", "--transactions", "300", "--faults", "0.1",
                   "--baud", "19200", "--chunking", "idle", "--idle-chars", "4", "--packet", "32",
                   "--jitter-us", "0")
    _, pchunks = read_hex(per["hex"])
    _, ichunks = read_hex(idle["hex"])
    ends = [t for t, _ in pchunks]
    expect(b"".join(c for _, c in pchunks) == b"".join(c for _, c in ichunks),
           "per-byte and idle-flush captures carry different bytes")
    i = 0
    for t, c in ichunks:
        last = i + len(c) - 1
        for k in range(i + 1, last + 1):
            expect(ends[k] - ends[k - 1] - 11 * 10**9 // 19200 <= idle_ns + 10,
                   f"idle-flush read at {t} holds a silence longer than the idle wait")
        silent_after = last + 1 == len(ends) or \
            ends[last + 1] - 11 * 10**9 // 19200 - ends[last] > idle_ns - 10
        expect(silent_after or len(c) % 32 == 0,
               f"idle-flush read at {t} ends before the line is idle")
        expect(t >= ends[last], f"idle-flush read at {t} precedes its last byte's end")
        i = last + 1
    expect(len(ichunks) < len(pchunks) / 4, "the idle-flush model hardly batches anything")
    # Packets never exceed the packet size unless the host merged them; with no jitter and a
    # long latency timer, a full packet is sent as soon as it is full.
    big = sim.run("chunk_packet", "--seed", "3", "--transactions", "200", "--chunking", "usb",
                  "--packet", "8", "--latency-ms", "200", "--jitter-us", "0")
    _, chunks = read_hex(big["hex"])
    expect(max(len(c) for _, c in chunks) == 8, "packet size not honoured")


def check_faults(sim):
    clean = sim.run("clean", "--seed", "5", "--transactions", "600")
    _, recs = read_truth(clean["truth"])
    expect(all(r["kind"] == "frame" for r in recs), "clean traffic has noise records")
    expect(all(not r["faults"] for r in recs), "clean traffic has faults")
    fcs = {r["fc"] for r in recs}
    for fc in (1, 2, 3, 5, 6, 8, 0x10, 0x11, 0x14, 0x16, 0x17, 0x18, 0x2B, 0x41):
        expect(fc in fcs, f"function code {fc:#04x} never appears in 600 clean transactions")
    expect({r["slave"] for r in recs} == {1, 2, 3, 4, 17}, "not every device answers")
    dirty = sim.run("dirty", "--seed", "5", "--transactions", "1500", "--faults", "1")
    _, recs = read_truth(dirty["truth"])
    seen = set()
    for r in recs:
        if r["kind"] == "frame":
            seen |= set(r["faults"])
            if "broadcast" in r["faults"]:
                expect(r["slave"] == 0 and r["fc"] in (5, 6, 0x0F, 0x10), "broadcast is not a write")
            if "exception" in r["faults"]:
                expect(r["fc"] & 0x80, "exception fault on a normal response")
        else:
            seen.add("noise:" + r["cause"])
    for key in ("crc", "t1.5", "t3.5", "timeout", "truncated", "wrong_slave", "exception",
                "broadcast", "noise:burst", "noise:turnaround"):
        expect(key in seen, f"fault {key} never injected at --faults 1")
    only = sim.run("only_crc", "--seed", "5", "--transactions", "300", "--faults", "1",
                   "--fault-kinds", "crc", "--devices", "yakotec")
    _, recs = read_truth(only["truth"])
    # YAKOTEC answers a request with a bad CRC with its exception 01 (device document).
    answered = [(a, b) for a, b in zip(recs, recs[1:])
                if "crc" in a["faults"] and a["role"] == "request" and b["role"] == "response"
                and b["txn"] == a["txn"]]
    expect(answered, "YAKOTEC never answered a bad-CRC request")
    for _, b in answered:
        expect(bytes.fromhex(b["hex"])[2] == 1 and b["fc"] & 0x80, "YAKOTEC bad-CRC answer")


def check_scorer(sim):
    p = sim.run("score", "--seed", "9", "--transactions", "400", "--faults", "0.2")
    truth = score.load(p["truth"])
    t3_5 = score.line_times(p["truth"])[1]
    s = score.score(truth, truth, t3_5)
    expect(s["found"] == s["truth_frames"] and s["true_frames"] == s["decoded_frames"],
           "truth against itself is not 100%")
    expect(s["bytes_ok"] == 1 and s["paired"] == s["pairs"] and s["false_pairs"] == 0,
           "truth against itself: bytes or pairing not perfect")
    expect(s["pairs"] > 300, "too few scorable pairs")

    def rescore(records):
        # Positions are recomputed as a decoder's output would give them.
        out = []
        pos = 0
        for r in records:
            r = dict(r)
            r["_pos"] = pos
            pos += len(r["_hex"]) // 2
            out.append(r)
        return score.score(truth, out, t3_5)

    frames = [i for i, r in enumerate(truth) if r["kind"] == "frame"]
    # 1. Two frames glued into one: recall and precision drop, bytes still add up.
    i = frames[10]
    glued = dict(truth[i])
    glued["_hex"] = truth[i]["_hex"] + truth[i + 1]["_hex"]
    s = rescore(truth[:i] + [glued] + truth[i + 2:])
    expect(s["found"] == s["truth_frames"] - 2, f"glued frames: found {s['found']}")
    expect(s["true_frames"] < s["decoded_frames"] and s["bytes_ok"] == 1, "glued frames")
    # 2. A byte dropped: byte accounting fails.
    cut = dict(truth[frames[20]])
    cut["_hex"] = cut["_hex"][2:]
    s = rescore(truth[:frames[20]] + [cut] + truth[frames[20] + 1:])
    expect(s["bytes_ok"] == 0, "a dropped byte went unnoticed")
    # 3. An intact frame reported as noise: a recall miss.
    noise = dict(truth[frames[30]], kind="noise")
    s = rescore(truth[:frames[30]] + [noise] + truth[frames[30] + 1:])
    expect(s["found"] == s["truth_frames"] - 1, "frame-as-noise not counted as a miss")
    # 4. A response given another request's txn: one lost pair and one false pair.
    k = next(i for i in frames[40:] if truth[i]["role"] == "response" and not truth[i]["faults"])
    wrong = dict(truth[k], txn=truth[frames[0]]["txn"])
    s = rescore(truth[:k] + [wrong] + truth[k + 1:])
    expect(s["paired"] < s["pairs"] and s["false_pairs"] >= 1, "wrong txn not counted")
    # 5. Timing flags: a t3.5 flag after a long silence and a t1.5 flag on a frame sent
    # without a pause are false; the same flags where the truth has those faults are true.
    silent = next(i for i in frames[1:] if truth[i]["t"] - truth[i - 1]["t_end"] > 10 * t3_5)
    clean = next(i for i in frames if "t1.5" not in truth[i]["faults"])
    flagged = [dict(r) for r in truth]
    flagged[silent]["issues"] = ["t3.5"]
    flagged[clean]["issues"] = (flagged[clean].get("issues") or []) + ["t1.5"]
    s = rescore(flagged)
    expect(s["t35_false"] == 1 and s["t15_false"] == 1 and s["t35_flagged"] == 1,
           f"false timing flags not counted: {s['t35_false']} t3.5, {s['t15_false']} t1.5")
    expect(not score.verdict(s, 0.9)[2], "a false timing flag did not fail the configuration")
    paused = [i for i in frames if "t1.5" in truth[i]["faults"]]
    expect(paused, "no t1.5 fault in the scorer's traffic")
    flagged = [dict(r) for r in truth]
    for i in paused:
        flagged[i]["issues"] = ["t1.5"]
    s = rescore(flagged)
    expect(s["t15_flagged"] == len(paused) and s["t15_false"] == 0, "true t1.5 flags miscounted")


def gaps_ns(path):
    """Truth records with exact integer t/t_end in ns, and the silence before each."""
    _, recs = read_truth(path)
    times = raw_truth_times(path)
    out = []
    prev_end = None
    for r, (t0, t1) in zip(recs, times):
        r = dict(r, t0=t0, t1=t1, before=None if prev_end is None else t0 - prev_end)
        prev_end = t1
        out.append(r)
    return out


def check_heavy(sim):
    """The heavy profile: deterministic, exact truth, every sick-bus fault really on the
    wire with the timing it promises, about 10% of transactions hit by default; and the miss
    classifier (tools/accuracy/misses.py) names synthetic misses right."""
    args = ["--profile", "heavy", "--seed", "17", "--transactions", "300", "--chunking", "usb",
            "--packet", "4", "--latency-ms", "1"]
    a = sim.run("heavy_det_a", *args)
    b = sim.run("heavy_det_b", *args)
    for k in a:
        da = open(a[k], "rb").read().replace(b"heavy_det_a", b"heavy_det_x")
        db = open(b[k], "rb").read().replace(b"heavy_det_b", b"heavy_det_x")
        expect(da == db, f"heavy profile: same seed gave different {k} files")

    common = ["--profile", "heavy", "--seed", "5", "--transactions", "600", "--faults", "1",
              "--baud", "115200"]
    per = sim.run("heavy_all", *common)
    usb = sim.run("heavy_all_usb", *common, "--chunking", "usb", "--packet", "4",
                  "--latency-ms", "1")
    _, pchunks = read_hex(per["hex"])
    _, uchunks = read_hex(usb["hex"])
    stream = b"".join(c for _, c in pchunks)
    expect(stream == b"".join(c for _, c in uchunks), "heavy: USB and per-byte bytes differ")
    expect(open(per["truth"]).read().split("\n", 1)[1] == open(usb["truth"]).read().split("\n", 1)[1],
           "heavy: chunking changed the truth")
    prev = None
    for t, c in uchunks:
        expect(prev is None or t > prev, "heavy USB: timestamps go backwards")
        prev = t
    recs = gaps_ns(per["truth"])
    expect(b"".join(bytes.fromhex(r["hex"]) for r in recs) == stream, "heavy: truth != capture")
    t3_5 = 1_750_000  # ns, fixed above 19200 baud
    seen = set()
    present = {1, 2, 3, 4, 17}
    for i, r in enumerate(recs):
        data = bytes.fromhex(r["hex"])
        expect(r["before"] is None or r["before"] >= 0, f"heavy: records overlap at {r['t']}")
        nxt = recs[i + 1] if i + 1 < len(recs) else None
        if r["kind"] == "noise":
            seen.add("noise:" + r["cause"])
            if r["cause"] == "glitch":
                expect(len(data) == 1, "a glitch is one byte")
                expect(50_000 <= r["before"] <= 150_000, f"glitch {r['before']} ns after its frame")
            if r["cause"] == "burst" and nxt and nxt["kind"] == "frame" and nxt["before"] < t3_5:
                seen.add("burst touching the next frame")
            if r["cause"] == "burst" and i > 0 and recs[i - 1]["kind"] == "frame" \
                    and r["before"] < t3_5:
                seen.add("burst touching the previous frame")
            continue
        faults = set(r["faults"])
        seen |= faults
        if "truncated" in faults:
            expect(0 < len(data) < r["intended_size"], f"truncated frame {r['hex']}")
            seen.add("truncated " + r["role"])
        elif "crc" in faults:
            expect(len(data) >= 4 and crc16(data) != 0, f"crc fault with a valid CRC: {r['hex']}")
            expect(r["flipped"] and all(0 <= k < len(data) for k in r["flipped"]), "flipped")
            seen |= {f"flip at {k}" for k in r["flipped"] if k < 2}
        else:
            expect(crc16(data) == 0, f"intact frame with a bad CRC: {r['hex']}")
        if r["device"] == "absent":
            expect(data[0] not in present and "timeout" in faults, f"absent slave {r['hex']}")
            seen.add("absent slave")
        prev_rec = recs[i - 1] if i > 0 else None
        if (r["role"] == "response" and prev_rec and prev_rec["kind"] == "frame"
                and prev_rec["txn"] == r["txn"] and 100_000 <= r["before"] < 700_000):
            seen.add("early response")  # 0.1-0.7 ms: before t1.5 (0.75 ms)
    for key in ("crc", "truncated request", "truncated response", "flip at 0", "flip at 1",
                "t1.5", "t3.5", "timeout", "wrong_slave", "exception", "broadcast",
                "absent slave", "early response", "noise:burst", "noise:turnaround",
                "noise:glitch", "burst touching the next frame",
                "burst touching the previous frame"):
        expect(key in seen, f"heavy --faults 1: never saw {key}")

    # The default rate: about one transaction in ten shows a fault or touches noise.
    p = sim.run("heavy_rate", "--profile", "heavy", "--seed", "3", "--transactions", "2000")
    _, recs = read_truth(p["truth"])
    txns, hit = set(), set()
    for i, r in enumerate(recs):
        if r["kind"] == "frame":
            txns.add(r["txn"])
            if r["faults"]:
                hit.add(r["txn"])
        else:
            hit |= {recs[j]["txn"] for j in (i - 1, i + 1)
                    if 0 <= j < len(recs) and recs[j]["kind"] == "frame"}
    share = len(hit) / len(txns)
    expect(0.07 <= share <= 0.16, f"heavy default: {share:.3f} of transactions faulty")
    r = subprocess.run([sim.exe, "--profile", "heavy", "--fault-kinds", "crc", "--out",
                        os.path.join(sim.work, "x.hex")], capture_output=True, text=True)
    expect(r.returncode == 2 and "crc" in r.stderr, "heavy accepted the classic kind crc")

    # The classifier, on misses made by hand from the truth.
    truth = score.load(per["truth"])

    def classes(records):
        out, pos = [], 0
        for x in records:
            x = dict(x, _pos=pos)
            pos += len(x["_hex"]) // 2
            out.append(x)
        s = score.score(truth, out, score.line_times(per["truth"])[1])
        return [misses.classify(f, truth, out)[0] for f in s["_misses"]]

    def index(pred):
        return next(i for i in range(1, len(truth) - 1) if pred(truth[i - 1], truth[i],
                                                                 truth[i + 1]))

    intact = lambda r: r["kind"] == "frame" and not r["faults"]  # noqa: E731
    g = index(lambda p, r, n: intact(r) and n["kind"] == "noise" and n["cause"] == "glitch")
    glued = dict(truth[g], _hex=truth[g]["_hex"] + truth[g + 1]["_hex"])
    expect(classes(truth[:g] + [glued] + truth[g + 2:]) == ["glitch absorbed"], "glitch absorbed")
    n = index(lambda p, r, n: r["kind"] == "noise" and r["cause"] == "burst" and intact(n))
    merged = dict(truth[n], _hex=truth[n]["_hex"] + truth[n + 1]["_hex"])
    expect(classes(truth[:n] + [merged] + truth[n + 2:]) == ["noise absorbed"], "noise absorbed")
    f = index(lambda p, r, n: intact(r))
    expect(classes(truth[:f] + [dict(truth[f], kind="noise")] + truth[f + 1:]) == ["as noise"],
           "as noise")


def check_decode_heavy(sim, rtuscope):
    """The heavy profile decodes with every byte accounted for, by rtuscope and by the
    reference decoder (tools/accuracy/ref_decoder.py), per byte and through a small-packet
    USB adapter; both stay above a loose floor, and every miss gets a class."""
    for chunking, extra in (("perbyte", []), ("usb", ["--packet", "8", "--latency-ms", "2"])):
        for baud, seed in (("9600", "23"), ("115200", "29")):
            name = f"heavy_decode_{chunking}_{baud}"
            # Three times the default rate: more misses for the classifier to sort.
            p = sim.run(name, "--profile", "heavy", "--seed", seed, "--transactions", "600",
                        "--faults", "0.3", "--baud", baud, "--chunking", chunking, *extra)
            decoded = os.path.join(sim.work, name + ".decoded.jsonl")
            with open(decoded, "w") as out:
                subprocess.run([rtuscope, "decode", p["hex"], "--format", "jsonl"], stdout=out,
                               check=True)
            reference = os.path.join(sim.work, name + ".ref.jsonl")
            with open(reference, "w") as out:
                for r in ref_decoder.decode(*ref_decoder.read_capture(p["hex"])):
                    out.write(json.dumps({k: v for k, v in r.items() if not k.startswith("_")})
                              + "\n")
            for who, path in (("rtuscope", decoded), ("reference", reference)):
                s, missed = misses.analyse(p["truth"], path)
                recall = score.ratio(s["found"], s["truth_frames"])
                precision = score.ratio(s["true_frames"], s["decoded_frames"])
                print(f"{name} {who}: recall {recall:.4f} precision {precision:.4f} misses "
                      f"{sorted(m[0] for m in missed)}")
                expect(s["bytes_ok"] == 1, f"{name} {who}: bytes not accounted for")
                expect(recall >= 0.97 and precision >= 0.97, f"{name} {who}: below 97%")
                expect(all(m[0] in misses.CLASSES for m in missed), "unknown miss class")


def check_decode_clean(sim, rtuscope):
    """A clean capture decodes perfectly, from the per-byte hex file and from the same bytes
    as a Saleae data-table export."""
    p = sim.run("decode_clean", "--seed", "4", "--transactions", "300")
    for kind in ("hex", "csv"):
        decoded = os.path.join(sim.work, f"decode_clean.{kind}.decoded.jsonl")
        with open(decoded, "w") as out:
            subprocess.run([rtuscope, "decode", p[kind], "--format", "jsonl"], stdout=out,
                           check=True)
        s = score.score_files(p["truth"], decoded)
        print(kind, {k: v for k, v in s.items() if not k.startswith("_")})
        expect(s["bytes_ok"] == 1, f"{kind}: decoded records do not account for every byte")
        expect(s["found"] == s["truth_frames"], f"{kind}: recall {s['found']}/{s['truth_frames']}")
        expect(s["true_frames"] == s["decoded_frames"],
               f"{kind}: precision {s['true_frames']}/{s['decoded_frames']}")
        expect(s["paired"] == s["pairs"] and s["false_pairs"] == 0,
               f"{kind}: pairing {s['paired']}/{s['pairs']}, false pairs {s['false_pairs']}")
        expect(s["t35_false"] == 0 and s["t15_false"] == 0,
               f"{kind}: {s['t35_false']} false t3.5 and {s['t15_false']} false t1.5 flags")


def check_decode_bytes(sim, rtuscope):
    """Under heavy faults (half the transactions), decode still succeeds and puts every input
    byte into exactly one record, per byte and through the USB model."""
    for chunking in ("perbyte", "usb"):
        for baud in ("9600", "115200"):
            name = f"heavy_{chunking}_{baud}"
            p = sim.run(name, "--seed", "13", "--transactions", "400", "--faults", "0.5",
                        "--baud", baud, "--chunking", chunking)
            decoded = os.path.join(sim.work, name + ".decoded.jsonl")
            with open(decoded, "w") as out:
                subprocess.run([rtuscope, "decode", p["hex"], "--format", "jsonl"], stdout=out,
                               check=True)
            s = score.score_files(p["truth"], decoded)
            print(f"{name}: recall {score.ratio(s['found'], s['truth_frames']):.4f} "
                  f"precision {score.ratio(s['true_frames'], s['decoded_frames']):.4f}")
            expect(s["bytes_ok"] == 1, f"{name}: decoded records do not account for every byte")
            expect(s["t35_false"] == 0 and s["t15_false"] == 0,
                   f"{name}: {s['t35_false']} false t3.5 and {s['t15_false']} false t1.5 flags")


def pcapng_records(path):
    """[(link type, ns timestamp, event byte, payload)] of a pcapng file's packets
    (little-endian, one section, ns resolution: as rtusim writes it)."""
    import struct
    data = open(path, "rb").read()
    links, out, pos = [], [], 0
    while pos < len(data):
        kind, length = struct.unpack_from("<II", data, pos)
        if kind == 1:
            links.append(struct.unpack_from("<H", data, pos + 8)[0])
        elif kind == 6:
            iface, high, low, captured = struct.unpack_from("<IIII", data, pos + 8)
            packet = data[pos + 28:pos + 28 + captured]
            out.append((links[iface], (high << 32) | low, packet[8], packet[12:]))
        pos += length
    return out


def check_decode_recording(sim, rtuscope):
    """--pcapng writes the same reads as --out, as a live recording holds them (one RTAC
    DATA_RX_START record per read, the line and the timing resolution declared), and with
    the resolution pinned (--resolution-ms: a declared one may be raised by what the frames
    show, an estimated one starts elsewhere) both files decode to the same records and
    report, on a sick bus, per byte and through the USB model."""
    for chunking, resolution in (("perbyte", "0.001000 ms"), ("usb", "16 ms")):
        name = f"recording_{chunking}"
        p = sim.run(name, "--seed", "17", "--transactions", "400", "--profile", "heavy",
                    "--faults", "0.4", "--chunking", chunking, "--baud", "19200")
        recording = os.path.join(sim.work, name + ".pcapng")
        subprocess.run([sim.exe, "--seed", "17", "--transactions", "400", "--profile", "heavy",
                        "--faults", "0.4", "--chunking", chunking, "--baud", "19200",
                        "--pcapng", recording], check=True)
        _, reads = read_hex(p["hex"])
        records = pcapng_records(recording)
        expect(len(records) == len(reads), f"{name}: {len(records)} records for {len(reads)} reads")
        for (t, data), (link, stamp, event, payload) in zip(reads, records):
            expect(link == 250 and stamp == t and event == 2 and payload == bytes(data),
                   f"{name}: the read at {t} ns recorded as link {link}, time {stamp}, "
                   f"event {event}, {payload.hex()}")
        description = open(recording, "rb").read().decode("latin-1")
        expect(f"RS-485 19200 8E1; rtusim; timing resolution {resolution}" in description,
               f"{name}: the interface does not declare the line and {resolution}")
        outputs = []
        pinned = ["--resolution-ms", resolution.split()[0]]
        for path in (p["hex"], recording):
            decoded = subprocess.run([rtuscope, "decode", path, "--format", "jsonl", *pinned],
                                     check=True, capture_output=True, text=True).stdout
            report = subprocess.run([rtuscope, "report", path, "--format", "json", *pinned],
                                    check=True, capture_output=True, text=True).stdout
            capture, *rest = decoded.splitlines()
            capture = json.loads(capture)
            expect(capture["source"] == path, f"{name}: capture line names {capture['source']}")
            report = json.loads(report)
            report["capture"].pop("source")
            outputs.append((rest, report))
        expect(len(outputs[0][0]) > 800, f"{name}: only {len(outputs[0][0])} records decoded")
        expect(outputs[0][0] == outputs[1][0], f"{name}: the recording decodes differently")
        expect(outputs[0][1] == outputs[1][1], f"{name}: the recording reports differently")
        print(f"{name}: {len(records)} reads, {len(outputs[0][0])} records, same from both")


def check_captures(sim, rtuscope, source_dir):
    """Every simulated capture in captures/ is what its provenance command writes today, and
    rtuscope decodes it accurately (clean: 100% frames; with faults: at least 99%)."""
    captures = os.path.join(source_dir, "captures")
    truths = sorted(f for f in os.listdir(captures) if f.endswith(".truth.jsonl"))
    expect(truths, "no simulated captures (*.truth.jsonl) in captures/")
    for name in truths:
        truth_path = os.path.join(captures, name)
        header, _ = read_truth(truth_path)
        command = header["generator"].split()
        expect(command[0] == "rtusim", f"{name}: generator is not an rtusim command")
        # Re-run it with the same relative paths, in a scratch tree.
        scratch = os.path.join(sim.work, "rerun")
        os.makedirs(os.path.join(scratch, "captures"), exist_ok=True)
        subprocess.run([sim.exe, *command[1:]], check=True, cwd=scratch)
        outputs = [command[i + 1] for i, a in enumerate(command) if a in ("--out", "--truth",
                                                                           "--saleae")]
        expect(os.path.join("captures", name) in outputs, f"{name}: command does not write it")
        for rel in outputs:
            fresh = open(os.path.join(scratch, rel), "rb").read()
            kept = open(os.path.join(source_dir, rel), "rb").read()
            expect(fresh == kept, f"{rel} differs from what its provenance command writes now; "
                   f"regenerate it with: {header['generator']}")
        hex_path = next(os.path.join(source_dir, r) for r in outputs if r.endswith(".hex"))
        decoded = os.path.join(sim.work, name + ".decoded")
        with open(decoded, "w") as out:
            subprocess.run([rtuscope, "decode", hex_path, "--format", "jsonl"], stdout=out,
                           check=True)
        s = score.score_files(truth_path, decoded)
        target = 1.0 if "--faults" not in command else 0.99
        recall = score.ratio(s["found"], s["truth_frames"])
        precision = score.ratio(s["true_frames"], s["decoded_frames"])
        print(f"{name}: recall {recall:.4f} precision {precision:.4f} bytes_ok {s['bytes_ok']}")
        expect(s["bytes_ok"] == 1, f"{name}: decoded records do not account for every byte")
        expect(recall >= target and precision >= target, f"{name}: below {target}")
        expect(s["t35_false"] == 0 and s["t15_false"] == 0, f"{name}: false timing flags")


def main():
    exe, work, check = sys.argv[1:4]
    sim = Sim(exe, os.path.join(work, check))
    if check == "decode_clean":
        check_decode_clean(sim, sys.argv[4])
    elif check == "decode_bytes":
        check_decode_bytes(sim, sys.argv[4])
    elif check == "decode_heavy":
        check_decode_heavy(sim, sys.argv[4])
    elif check == "decode_recording":
        check_decode_recording(sim, sys.argv[4])
    elif check == "captures":
        check_captures(sim, sys.argv[4], sys.argv[5])
    else:
        {"determinism": check_determinism, "truth": check_truth, "chunking": check_chunking,
         "faults": check_faults, "scorer": check_scorer, "heavy": check_heavy}[check](sim)
    print(f"{check}: ok")


if __name__ == "__main__":
    main()
