#!/usr/bin/env python3
"""Live capture against real Modbus peers on the virtual RS-485 bus.

rtuvbus provides three pseudo-terminal endpoints: mbpoll (libmodbus) is the master on
ep0, a slave (our libmodbus server, or Debian's pymodbus) answers on ep1, and
`rtuscope live -w` sniffs ep2. Afterwards:
  * every byte the peers wrote (the bus log) was captured, in order;
  * every burst a peer wrote is one CRC-valid frame, requests paired with their responses,
    the request to an absent slave timed out, and every frame decoded (function named);
  * the timing flags hold on the wire (the bus log's times): no t1.5 flag on a burst, and
    no t3.5 flag on a silence longer than t3.5 and what a loaded host's reads may lose;
  * `rtuscope decode` of the pcapng written meanwhile gives the same records.
"""
import argparse
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

from bus_helpers import fail, stop_all  # also puts tools/pylib on the path
from pcapng_reads import read_times
from rtu_timing import char_seconds, t1_5_seconds, t3_5_seconds

SLAVE = 17
ABSENT = 99
BAUD = 19200
SNIFFER = 2  # the endpoint rtuscope reads


def read_lines(proc, count, what, deadline=20.0):
    lines = []
    end = time.monotonic() + deadline
    while len(lines) < count:
        if time.monotonic() > end:
            fail(f"{what}: no output")
        line = proc.stdout.readline()
        if not line:
            fail(f"{what} ended early (exit {proc.wait()})")
        lines.append(line.strip())
    return lines


def wait_for_stderr(proc, needle, what, deadline=20.0):
    end = time.monotonic() + deadline
    seen = []
    while time.monotonic() < end:
        line = proc.stderr.readline()
        if not line:
            break
        seen.append(line)
        if needle in line:
            return seen
    fail(f"{what} did not say '{needle}': {''.join(seen)}")


def bus_bursts(log_path):
    """Bursts from the bus log, as (writer, hex, wire start, wire end) in seconds: reads of
    one writer that follow each other on the wire without a pause are one burst (a writer's
    frame may reach the bus in several reads)."""
    bursts = []
    who = start = None
    with open(log_path) as f:
        for line in f:
            line = line.strip()
            if line.startswith("# from ep"):
                fields = line[len("# from ep"):].split()
                who, start = int(fields[0]), float(fields[2])
                continue
            if not line or line.startswith("#"):
                continue
            t, hexbytes = line.split()
            if bursts and bursts[-1][0] == who and start - bursts[-1][2] < 2e-6:
                bursts[-1][1] += hexbytes
                bursts[-1][3] = float(t)
            else:
                bursts.append([who, hexbytes, start, float(t)])
    return [tuple(b) for b in bursts]


def late_deliveries(log_path, endpoint):
    """Where the bus's own thread woke late and handed `endpoint` bytes later than the wire
    had them, as (wire end of the first byte handed over, lateness) in seconds: there the
    endpoint saw a pause the wire never had, which no reader can tell from a real one."""
    late = []
    prefix = f"# late to ep{endpoint}: byte ending "
    with open(log_path) as f:
        for line in f:
            if line.startswith(prefix):
                fields = line[len(prefix):].split()
                wire_end, delivered = float(fields[0]), float(fields[3])
                late.append((wire_end, delivered - wire_end))
    return late


def bus_lateness_within(late, start, end):
    """The most the bus delivered late a byte whose wire end lies in [start, end]."""
    return max((lateness for wire_end, lateness in late if start < wire_end <= end + 1e-9),
               default=0.0)


# How late a loaded test machine (two cores, sanitizers) may read a byte beyond the 1 ms
# that rtuscope assumes of a host's reads. The last byte before a silence arrives alone, so a
# late read of it shortens the silence rtuscope measures without any sign in the reads. The
# silences that matter here are far from this: answers come 0.1-2 ms after their request,
# and the next request 20 ms or more after that.
HOST_LATENESS = 5e-3


def sniffer_pauses(reads, byte_count, char_time):
    """For each byte the sniffer read, the pause its port showed before it, in seconds, as
    rtuscope measures it (only where a read begins; None inside a read, at the first read,
    and next to a read marked late, whose time shows no pause)."""
    pauses = []
    prev_t = prev_late = None
    for t, data, late in reads:
        t /= 1e9
        shown = prev_t is not None and not late and not prev_late
        pauses.append(t - prev_t - len(data) * char_time if shown else None)
        pauses.extend([None] * (len(data) - 1))
        prev_t, prev_late = t, late
    return pauses[:byte_count]


# Pauses inside a frame that the sniffer's port showed although the wire had none, or
# silences before a frame shorter than the wire's: its host delivered a byte late, where
# rtuscope cannot see it (the kernel's own delivery, or the bus's thread; the reading
# thread's lateness it measures and marks). A t1.5 or t3.5 flag there is the port's truth,
# not the wire's; tolerated in a few frames of a run on a loaded machine.
UNSEEN_LATENESS_FRAMES = 3


def check_timing_flags(bursts, frames, baud, pauses, late):
    """Every timing flag is true on the wire: a t3.5 flag only where the bus was silent
    for less than t3.5 before the frame (give or take the host's lateness), and no t1.5 flag
    (a burst has no pause inside). Either may stand where the sniffer's port showed what the
    wire had not (`pauses`, from sniffer_pauses()), which rtuscope could not tell from the
    truth, in a few frames at most. `late`: where the bus delivered late
    (late_deliveries()), said with the flag.
    Returns how many t3.5 flags there were and how many frames broke t3.5 on the wire."""
    t3_5 = t3_5_seconds(baud)
    t1_5 = t1_5_seconds(baud)
    resolution = 1e-3  # what rtuscope takes a pseudo-terminal's reads to be good for
    flagged = violations = unseen = 0
    first_byte = 0
    for i, ((_, hexbytes, start, end), frame) in enumerate(zip(bursts, frames)):
        size = len(hexbytes) // 2
        frame_start = first_byte
        inner = [p for p in pauses[first_byte + 1:first_byte + size] if p is not None]
        first_byte += size
        silence = start - bursts[i - 1][3] if i > 0 else None
        violations += silence is not None and silence < t3_5
        issues = frame.get("issues") or []
        if "t1.5" in issues:
            shown = max(inner, default=None)
            if shown is None or shown - resolution <= t1_5:
                fail(f"t1.5 flag on a frame the bus sent without a pause, and the sniffer's "
                     f"reads showed none either (longest {shown}): {frame}")
            unseen += 1
            print(f"t1.5 flag where the sniffer's port showed a {shown * 1e3:.3f} ms pause the "
                  f"wire did not have (the bus delivered it "
                  f"{bus_lateness_within(late, start, end) * 1e3:.3f} ms late): {frame['hex']}")
        if "t3.5" in issues:
            flagged += 1
            if silence is None or silence >= t3_5 + HOST_LATENESS:
                # The port's truth, where the last byte before the silence reached the
                # sniffer late (the kernel's delivery or the bus's thread): rtuscope flags
                # only a silence shorter than t3.5 by its resolution, so a port that showed
                # one that long or longer, or none, would be a flag it invented.
                shown = pauses[frame_start] if frame_start < len(pauses) else None
                if silence is None or shown is None or shown + resolution >= t3_5 + 1e-6:
                    said = "none before it" if silence is None else f"{silence * 1e3:.3f} ms"
                    fail(f"t3.5 flag where the bus was silent for {said} "
                         f"(t3.5 is {t3_5 * 1e3:.3f} ms) and the sniffer's port showed "
                         f"{'no silence' if shown is None else f'{shown * 1e3:.3f} ms'}: "
                         f"{frame}")
                unseen += 1
                late_by = bus_lateness_within(late, bursts[i - 1][2], bursts[i - 1][3])
                print(f"t3.5 flag where the sniffer's port showed a {shown * 1e3:.3f} ms "
                      f"silence and the wire {silence * 1e3:.3f} ms (the bus delivered the "
                      f"frame before {late_by * 1e3:.3f} ms late): {frame['hex']}")
    if unseen > UNSEEN_LATENESS_FRAMES:
        fail(f"{unseen} frames flagged t1.5 or t3.5 for what only the sniffer's port showed: "
             f"more than a loaded host explains")
    return flagged, violations


def master_commands(port, baud):
    base = ["mbpoll", "-m", "rtu", "-b", str(baud), "-P", "even", "-1", "-o", "0.5"]
    reads = [
        ["-a", str(SLAVE), "-t", "4", "-r", "1", "-c", "10"],   # FC03
        ["-a", str(SLAVE), "-t", "3", "-r", "5", "-c", "4"],    # FC04
        ["-a", str(SLAVE), "-t", "0", "-r", "1", "-c", "16"],   # FC01
        ["-a", str(SLAVE), "-t", "1", "-r", "3", "-c", "9"],    # FC02
        ["-a", str(SLAVE), "-t", "4", "-r", "1", "-c", "100"],  # FC03, a 205-byte response
    ]
    writes = [
        (["-a", str(SLAVE), "-t", "4", "-r", "20"], ["1234"]),         # FC06
        (["-a", str(SLAVE), "-t", "4", "-r", "30"], ["1", "2", "3"]),  # FC16
        (["-a", str(SLAVE), "-t", "0", "-r", "7"], ["1"]),             # FC05
        (["-a", str(SLAVE), "-t", "0", "-r", "10"], ["1", "0", "1"]),  # FC15
    ]
    cmds = []
    for _ in range(2):
        for r in reads:
            cmds.append(base + r + [port])
        for opts, values in writes:
            cmds.append(base + opts + [port] + values)
    cmds.append(base + ["-a", str(ABSENT), "-t", "4", "-r", "1", "-c", "2", port])
    return cmds


def load_jsonl(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def python_with_pymodbus():
    for candidate in (sys.executable, "/usr/bin/python3"):
        if candidate and subprocess.run([candidate, "-c", "import pymodbus"],
                                        capture_output=True).returncode == 0:
            return candidate
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--vbus", required=True)
    ap.add_argument("--slave", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--scenario", required=True)
    ap.add_argument("--baud", type=int, default=BAUD)
    # USB adapter model on the sniffer's endpoint: latency timer and packet size. The
    # peers answer as fast as they can (0.1-0.7 ms at 115200, faster than t1.5), so
    # requests and responses share transfers and frames are cut at packet boundaries.
    ap.add_argument("--usb-latency-ms", type=float)
    ap.add_argument("--usb-packet", type=int)
    ap.add_argument("--slave-kind", choices=["libmodbus", "pymodbus"])
    # Bytes reach the adapter model one by one at the line rate, so a 1 ms latency timer
    # hands over a long frame in a read per millisecond, as a real adapter does, instead of
    # each writer's frame arriving whole.
    ap.add_argument("--wire-rate", action="store_true")
    args = ap.parse_args()
    baud = args.baud
    if shutil.which("mbpoll") is None:
        fail("mbpoll is not installed (tools/debian-packages.txt)")
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    log = os.path.join(args.work, "bus.hex")
    pcapng = os.path.join(args.work, "live.pcapng")
    live_out = os.path.join(args.work, "live.jsonl")
    report_path = os.path.join(args.work, "report.json")

    vbus_cmd = [args.vbus, "-n", "3", "--baud", str(baud), "--parity", "E", "--log", log]
    if args.wire_rate:
        vbus_cmd.append("--per-byte")
    usb = args.scenario == "usb_chunking" or args.usb_latency_ms is not None
    if usb:
        vbus_cmd += ["--usb", "2", "--usb-latency-ms", str(args.usb_latency_ms or 16)]
        if args.usb_packet:
            vbus_cmd += ["--usb-packet", str(args.usb_packet)]
    pymodbus = args.scenario == "pymodbus_slave" or args.slave_kind == "pymodbus"

    def run_session():
        """One capture on a fresh bus; rtuscope live's stderr."""
        vbus = subprocess.Popen(vbus_cmd, stdout=subprocess.PIPE, text=True)
        procs = [vbus]
        try:
            master_ep, slave_ep, sniff_ep = read_lines(vbus, 3, "rtuvbus")
            if pymodbus:
                py = python_with_pymodbus()
                if py is None:
                    fail("python3-pymodbus is not installed (tools/debian-packages.txt)")
                slave_cmd = [py, os.path.join(os.path.dirname(__file__), "pymodbus_slave.py")]
            else:
                slave_cmd = [args.slave]
            # pymodbus cannot open a pty with parity (see pymodbus_slave.py); a pty has none.
            slave_parity = "N" if pymodbus else "E"
            slave = subprocess.Popen(
                slave_cmd + [slave_ep, str(SLAVE), str(baud), slave_parity, "1"],
                stdout=subprocess.PIPE, text=True)
            procs.append(slave)
            read_lines(slave, 1, "slave")
            live = subprocess.Popen([args.rtuscope, "live", sniff_ep, "--baud", str(baud),
                                     "--parity", "E", "--format", "jsonl", "-o", live_out,
                                     "-w", pcapng, "--timeout-ms", "300", "--report", report_path],
                                    stderr=subprocess.PIPE, text=True)
            procs.append(live)
            notes = wait_for_stderr(live, "listening on", "rtuscope live")
            if not any("parity" in n for n in notes):
                fail("rtuscope live did not say that the pty has no parity")
            time.sleep(1.0)  # pymodbus opens its port asynchronously after printing "ready"
            for cmd in master_commands(master_ep, baud):
                r = subprocess.run(cmd, capture_output=True, text=True, timeout=30)
                absent = f"-a {ABSENT}" in " ".join(cmd)
                if r.returncode != 0 and not absent:
                    fail(f"{' '.join(cmd)} failed: {r.stdout}{r.stderr}")
            time.sleep(0.5)  # the last response's t3.5 and the absent slave's timeout
            live.send_signal(signal.SIGTERM)
            _, err = live.communicate(timeout=20)
            if live.returncode != 0:
                fail(f"rtuscope live exited {live.returncode}: {err}")
            print(err, end="")
        finally:
            stop_all(procs)
        return err

    # Without an adapter model, --wire-rate hands rtuscope a byte per read at slow rates: the
    # recording is then replayed as a per-byte capture (runs of one-byte reads, framed ahead),
    # and step 5 holds that path to the live records too. Make sure it is the one taken.
    # A loaded machine (two cores, sanitizers) now and then reads two bytes at once; the runs
    # between such reads still take the per-byte path. A batching port would give several
    # bytes per read on average, far below this bound. Where a moment of the machine batched
    # more than that, the capture is taken again (at most three times): the reads are what
    # this case is about, not what it checks.
    # The bus's own thread can wake late too (a loaded machine): it then hands the sniffer
    # bytes a frame's length after the wire had them, and the sniffer sees a silence the
    # wire never had. One long enough for rtuscope to end a frame in (t3.5 plus the 20 ms it
    # allows for an adapter's delivery) is a true silence on the sniffer's port, no fault of
    # rtuscope's, and not what this test is about: the capture is taken again (three times
    # at most), as the bus log says why.
    per_byte_case = args.wire_rate and not usb
    attempts = 3
    ends_frames = t3_5_seconds(baud) + 20e-3
    for attempt in range(1, attempts + 1):
        for stale in (log, pcapng, live_out, report_path):
            if os.path.exists(stale):
                os.remove(stale)
        err = run_session()
        stalls = [lateness for _, lateness in late_deliveries(log, SNIFFER)
                  if lateness >= ends_frames]
        if stalls:
            message = (f"the bus delivered to the sniffer up to {max(stalls) * 1e3:.1f} ms "
                       f"late, a silence its port had and the wire had not")
            if attempt == attempts:
                fail(f"{message}, in {attempts} captures")
            print(f"capture {attempt}: {message}; taken again")
            continue
        if not per_byte_case:
            break
        sizes = re.search(r"(\d+) bytes in (\d+) reads", err)
        if sizes is None:
            fail(f"rtuscope live printed no summary of its reads: {err}")
        nbytes, reads = int(sizes.group(1)), int(sizes.group(2))
        if reads * 10 >= nbytes * 9:
            break
        message = f"{nbytes} bytes came in {reads} reads, not (nearly) one byte per read"
        if attempt == attempts:
            fail(f"{message}, in {attempts} captures")
        print(f"capture {attempt}: {message}; taken again")

    bursts = bus_bursts(log)
    records = load_jsonl(live_out)
    body = [r for r in records if r["kind"] in ("frame", "noise")]
    frames = [r for r in body if r["kind"] == "frame"]
    print(f"bus log: {len(bursts)} bursts; live: {len(frames)} frames, "
          f"{len(body) - len(frames)} noise records")

    # 1. Every byte, in order.
    bus_bytes = "".join(b[1] for b in bursts)
    live_bytes = "".join(r["hex"] for r in body)
    if bus_bytes != live_bytes:
        fail(f"captured bytes differ from the bus log:\n bus  {bus_bytes}\n live {live_bytes}")
    # 2. One frame per burst, CRC-valid, decoded, roles from who wrote it.
    if len(frames) != len(bursts) or len(body) != len(frames):
        fail(f"{len(bursts)} bursts on the bus but {len(frames)} frames, "
             f"{len(body) - len(frames)} noise records")
    for (who, hexbytes, _, _), frame in zip(bursts, frames):
        want_role = "request" if who == 0 else "response"
        if frame["hex"] != hexbytes or not frame["crc_ok"] or frame["role"] != want_role:
            fail(f"burst from ep{who} {hexbytes} became {frame}")
        if not frame.get("function"):
            fail(f"frame not decoded: {frame}")
    # 3. Pairing: each response shares the txn of the request just before it.
    answered = 0
    for i, frame in enumerate(frames):
        if frame["role"] == "response":
            req = frames[i - 1]
            if req["role"] != "request" or frame["txn"] is None or req["txn"] != frame["txn"]:
                fail(f"response not paired with its request: {req} / {frame}")
            if frame.get("latency_ms") is None:
                fail(f"response without latency: {frame}")
            answered += 1
    requests = [f for f in frames if f["role"] == "request"]
    timed_out = [f for f in requests if "timeout" in (f.get("issues") or [])]
    if answered != len(requests) - 1 or len(timed_out) != 1 or timed_out[0]["slave"] != ABSENT:
        fail(f"{answered} answered of {len(requests)} requests, timeouts: {timed_out}")
    functions = sorted({f["fc"] for f in requests})
    if functions != [1, 2, 3, 4, 5, 6, 15, 16]:
        fail(f"function codes seen: {functions}")

    # 4. The report written when the run stopped counts what was printed.
    with open(report_path) as f:
        report = json.load(f)
    slave = report["slaves"][str(SLAVE)]
    absent = report["slaves"][str(ABSENT)]
    if (slave["requests"] != len(requests) - 1 or slave["responses"] != answered
            or slave["timeouts"] != 0 or absent["timeouts"] != 1
            or report["totals"]["frames"] != len(frames)):
        fail(f"report disagrees with the records: totals {report['totals']}, "
             f"slave {SLAVE} {slave}, slave {ABSENT} {absent}")
    # Every answer's latency is either seen or hidden in the read that ended its request: a
    # USB adapter's transfer, or on the plain bus a read the host took late (its latency reads
    # 0 there, a lower bound only, so the report counts it apart rather than as 0 ms). A seen
    # one is an estimate within about one resolution step, 0 through an adapter that held the
    # answer back; on the plain bus they are measured.
    seen, unseen = slave["latency_samples"], slave["latency_unseen"]
    if seen + unseen != answered:
        fail(f"slave {SLAVE}: {seen} latencies seen and {unseen} unseen of {answered} answers")
    if seen > 0 and slave["latency_ms"] is None:
        fail(f"report has no latency for slave {SLAVE}: {seen} seen")
    if not usb and (seen == 0 or slave["latency_ms"]["max"] <= 0):
        fail(f"report has no latency for slave {SLAVE} on the plain bus: {slave['latency_ms']}")

    # 5. Timing flags are evidence, never invented.
    pauses = sniffer_pauses(read_times(pcapng), len(bus_bytes) // 2, char_seconds(baud))
    flagged, violations = check_timing_flags(bursts, frames, baud, pauses,
                                             late_deliveries(log, SNIFFER))
    print(f"t3.5: {flagged} flagged, none on a long silence; {violations} frames broke it "
          f"on the wire")

    # 6. The recording replays to the same records.
    replay = subprocess.run([args.rtuscope, "decode", pcapng, "--format", "jsonl"],
                            capture_output=True, text=True, timeout=60)
    if replay.returncode != 0 and "pcap import is not available" in replay.stderr:
        # This build has no pcapng reader yet: everything above was still checked.
        print("replay check skipped: this build cannot read pcapng")
        print(f"OK: {len(bursts)} bursts captured, {answered} transactions paired")
        return
    if replay.returncode != 0:
        fail(f"decode {pcapng}: {replay.stderr}")
    replayed = [json.loads(line) for line in replay.stdout.splitlines() if line.strip()]
    rbody = [r for r in replayed if r["kind"] in ("frame", "noise")]
    if rbody != body:
        for a, b in zip(body, rbody):
            if a != b:
                fail(f"replay differs:\n live   {a}\n replay {b}")
        fail(f"replay has {len(rbody)} records, live {len(body)}")
    header = [r for r in records if r["kind"] == "capture"]
    rheader = [r for r in replayed if r["kind"] == "capture"]
    for key in ("baud", "parity", "stop_bits", "timing_resolution_ms"):
        if header[0].get(key) != rheader[0].get(key):
            fail(f"header {key}: live {header[0].get(key)}, replay {rheader[0].get(key)}")
    # 7. Both reports judge timing by the resolution the reads showed by the end: the run's
    # (its summary names one it learned) and that of a report of the recording.
    learned = re.search(r"gaps below ([0-9.]+) ms were not observable", err)
    run_capture = report["capture"]
    if bool(learned) != run_capture["timing_resolution_learned"]:
        fail(f"the run's summary {'names' if learned else 'names no'} a learned resolution, its "
             f"report says {run_capture}")
    # The summary rounds to 0.1 ms, the report to 0.001 ms.
    if learned and abs(run_capture["timing_resolution_ms"] - float(learned.group(1))) > 0.051:
        fail(f"the run learned {learned.group(1)} ms, its report says {run_capture}")
    replayed_report = subprocess.run([args.rtuscope, "report", pcapng, "--format", "json", "-q"],
                                     capture_output=True, text=True, timeout=60)
    if replayed_report.returncode != 0:
        fail(f"report {pcapng}: {replayed_report.stderr}")
    replay_capture = json.loads(replayed_report.stdout)["capture"]
    for key in ("timing_resolution_ms", "timing_resolution_start_ms", "timing_resolution_learned",
                "timing_note"):
        if run_capture[key] != replay_capture[key]:
            fail(f"report {key}: run {run_capture[key]}, of the recording {replay_capture[key]}")
    print(f"OK: {len(bursts)} bursts captured, {answered} transactions paired, "
          f"replay identical ({len(rbody)} records), resolution "
          f"{run_capture['timing_resolution_ms']} ms"
          f"{' learned' if run_capture['timing_resolution_learned'] else ''} in both reports")


if __name__ == "__main__":
    main()
