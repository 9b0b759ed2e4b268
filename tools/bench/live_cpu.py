#!/usr/bin/env python3
"""CPU of `rtuscope live` on a saturated virtual bus, as a plant would see it.

    tools/bench/live_cpu.py [--baud 115200] [--seconds 60] [--usb-latency-ms 1]
                            [--build build] [--floor | --asio-floor]

A master and a slave endpoint of rtuvbus exchange CRC-valid Modbus frames back to back
(requests of 8 bytes, answers of 5-69 bytes, a pause of four characters between frames),
which keeps the line about 90% busy. Four characters is what many devices keep at any rate;
above 19200 baud the spec asks for 1.75 ms (18 characters at 115200), so this bus breaks t3.5
before nearly every frame, and rtuscope flags it wherever its reads show the silence.

The bus delivers byte by byte at the line rate, and rtuscope listens on a third endpoint that
receives through a USB-adapter model with the given latency timer: with 1 ms (the smallest a
common adapter has) a long answer arrives in a read per millisecond, as from a real FTDI
adapter, not in one read per frame. rtuscope writes JSON lines to /dev/null (LIVE_CPU_JSONL
names a file instead) and records a pcapng. Prints the line load, the CPU that rtuscope used
(the scheduler's nanosecond count, /proc/PID/task/*/schedstat) as a share of one core, and
rtuscope's own summary of its reads.

With --floor, tools/bench/read_floor listens instead of rtuscope: a blocking read() per batch
the port hands over and nothing else, the least CPU any program can use to hear the same
reads on this machine. rtuscope's figure minus that one is what its own work costs. With
--asio-floor, tools/bench/asio_read_floor listens: the same through Boost.Asio's reactor, as
rtuscope reads (epoll_wait, the read, and the read that finds the port empty before each
wait), which is the least an Asio program can use.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time
import tty

# tools/pylib, found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../pylib"))
from modbus_crc import with_crc  # noqa: E402  (after the path line)
from proc_usage import cpu_seconds_exact  # noqa: E402


def frames():
    """A polling cycle: read 1..32 registers of slave 1, answered."""
    cycle = []
    for qty in range(1, 33):
        request = bytes([1, 3, 0, 0, 0, qty])
        answer = bytes([1, 3, 2 * qty]) + bytes(range(2 * qty))
        cycle.append(with_crc(request))
        cycle.append(with_crc(answer))
    return cycle


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baud", type=int, default=115200)
    ap.add_argument("--seconds", type=float, default=60)
    ap.add_argument("--usb-latency-ms", type=float, default=1.0)
    ap.add_argument("--build", default=os.path.join(os.path.dirname(__file__), "../../build"))
    ap.add_argument("--floor", action="store_true",
                    help="measure tools/bench/read_floor (a bare blocking reader) instead")
    ap.add_argument("--asio-floor", action="store_true",
                    help="measure tools/bench/asio_read_floor (a bare Asio reader) instead")
    args = ap.parse_args()
    if args.floor and args.asio_floor:
        ap.error("--floor and --asio-floor measure different listeners: give one")
    floor = "read_floor" if args.floor else "asio_read_floor" if args.asio_floor else None
    listener = floor or "rtuscope live"
    char_s = 11 / args.baud  # 8E1
    work = tempfile.mkdtemp(prefix="rtuscope-livecpu-")
    links = os.path.join(work, "bus")
    procs = []
    live_log = open(os.path.join(work, "live.log"), "w")
    try:
        procs.append(subprocess.Popen(
            [os.path.join(args.build, "rtuvbus"), "-n", "3", "--baud", str(args.baud),
             "--link-dir", links, "--per-byte", "--usb", "2", "--usb-latency-ms", str(args.usb_latency_ms)],
            stdout=subprocess.DEVNULL))
        deadline = time.monotonic() + 10
        while not os.path.exists(os.path.join(links, "ep2")):
            if time.monotonic() > deadline:
                sys.exit("live_cpu: the virtual bus did not come up")
            time.sleep(0.05)
        if floor:
            command = [os.path.join(args.build, "tools", "bench", floor), os.path.join(links, "ep2")]
        else:
            command = [os.path.join(args.build, "rtuscope"), "live", os.path.join(links, "ep2"),
                       "--baud", str(args.baud), "--format", "jsonl",
                       "-o", os.environ.get("LIVE_CPU_JSONL", os.devnull),
                       "-w", os.path.join(work, "rec.pcapng")]
        live = subprocess.Popen(command, stderr=live_log)
        procs.append(live)
        time.sleep(1)
        writers = [os.open(os.path.join(links, f"ep{i}"), os.O_RDWR | os.O_NOCTTY)
                   for i in (0, 1)]
        for fd in writers:
            tty.setraw(fd)
            os.set_blocking(fd, False)  # each also hears the other: drained, never waited on
        cycle = frames()
        pause = 4 * char_s  # 3.5 characters and a little more: short of the spec's 1.75 ms
        start_cpu = cpu_seconds_exact(live.pid)
        start = time.monotonic()
        due = start
        busy = 0.0
        while time.monotonic() - start < args.seconds:
            for i, frame in enumerate(cycle):
                os.write(writers[i % 2], frame)
                for fd in writers:
                    try:
                        os.read(fd, 4096)
                    except BlockingIOError:
                        pass
                on_wire = len(frame) * char_s
                busy += on_wire
                due += on_wire + pause
                delay = due - time.monotonic()
                if delay > 0:
                    time.sleep(delay)
        elapsed = time.monotonic() - start
        used = cpu_seconds_exact(live.pid) - start_cpu
        print(f"{args.baud} baud, line {100 * busy / elapsed:.0f}% busy, USB latency "
              f"{args.usb_latency_ms:g} ms, {elapsed:.0f} s: {listener} used {used:.2f} s "
              f"of CPU = {100 * used / elapsed:.2f}% of a core")
        for fd in writers:
            os.close(fd)
        live.terminate()
        live.wait()
        live_log.close()
        with open(os.path.join(work, "live.log")) as f:
            summary = [line.strip() for line in f
                       if " reads: " in line or line.startswith("read_floor: ")]
        print(summary[-1] if summary else f"{listener} printed no summary of its reads")
    finally:
        for p in reversed(procs):
            p.terminate()
            p.wait()


if __name__ == "__main__":
    main()
