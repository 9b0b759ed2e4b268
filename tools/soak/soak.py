#!/usr/bin/env python3
"""Soak: `rtuscope live` on a virtual bus with simulated traffic, rotation on, for a given time.

A plant leaves the recorder running for weeks, so what must hold is what a short test cannot
see: memory that creeps, file descriptors that leak with every rotation, CPU that grows with
the length of the run, bytes lost at a file boundary. Every sample interval this samples the
recorder's RSS, open files and CPU time, and at the end it checks:
- RSS never exceeds its level over the first part of the run (10 minutes, or half of a shorter
  run) plus 10%;
- open files stay within 2 of the first sample (rotation closes what it opens);
- every byte the player wrote is in the recordings, read back as one rotation set;
- the run ends cleanly on SIGTERM (exit 0, a `stop` event).
The figures are printed as a table, one row per sample, and as a JSON summary line.
"""
import argparse
import glob
import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
import tty

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../pylib"))
from check_support import fail  # noqa: E402  (after the path line)
from proc_usage import cpu_seconds, open_files, rss_kb  # noqa: E402

RSS_MARGIN = 1.10
FD_MARGIN = 2


def parse_duration(text):
    units = {"s": 1, "m": 60, "h": 3600}
    if text[-1] in units:
        return float(text[:-1]) * units[text[-1]]
    return float(text)


def wait_for(predicate, timeout, what):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(0.05)
    fail(f"timed out waiting for {what}")


def load_traffic(path):
    """(seconds, bytes) per line of an rtusim text hex capture."""
    lines = []
    with open(path) as f:
        for line in f:
            if not line.strip() or line.startswith("#"):
                continue
            fields = line.split()
            lines.append((float(fields[0]), bytes(int(x, 16) for x in fields[1:])))
    return lines


class Player(threading.Thread):
    """Writes the simulated traffic onto the bus at its own pace, over and over, and counts
    every byte it writes."""

    def __init__(self, endpoint, traffic):
        super().__init__(daemon=True)
        self.fd = os.open(endpoint, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(self.fd)
        self.traffic = traffic
        self.period = traffic[-1][0] + 0.5
        self.written = 0
        self.stopping = threading.Event()

    def run(self):
        start = time.monotonic()
        lap = 0
        while not self.stopping.is_set():
            for t, data in self.traffic:
                due = start + lap * self.period + t
                delay = due - time.monotonic()
                if delay > 0 and self.stopping.wait(delay):
                    return
                os.write(self.fd, data)
                self.written += len(data)
            lap += 1

    def stop(self):
        self.stopping.set()
        self.join()
        os.close(self.fd)


def sample(pid):
    return rss_kb(pid), open_files(pid), cpu_seconds(pid)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", default="2m", help="how long to run: 90s, 2m, 2h")
    ap.add_argument("--interval", help="sample period (default: 1m, or a twelfth of a shorter run)")
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--vbus", required=True)
    ap.add_argument("--rtusim", required=True)
    ap.add_argument("--baud", type=int, default=19200)
    ap.add_argument("--rotate", default="1m", help="rotation of the recording (size or age)")
    ap.add_argument("--work", help="keep the files here (default: a temporary folder)")
    args = ap.parse_args()

    duration = parse_duration(args.duration)
    interval = parse_duration(args.interval) if args.interval else min(60.0, duration / 12)
    baseline_window = min(600.0, duration / 2)
    work = args.work or tempfile.mkdtemp(prefix="rtuscope-soak-")
    for old in glob.glob(os.path.join(work, "soak*.pcapng")):
        os.remove(old)  # a rerun in the same folder reads back only its own recordings
    os.makedirs(work, exist_ok=True)

    traffic_path = os.path.join(work, "traffic.hex")
    subprocess.run([args.rtusim, "--duration", "120", "--baud", str(args.baud), "--chunking",
                    "usb", "--faults", "0.05", "--seed", "7", "--out", traffic_path],
                   check=True, stdout=subprocess.DEVNULL)
    traffic = load_traffic(traffic_path)

    links = os.path.join(work, "bus")
    procs = []
    try:
        vbus = subprocess.Popen([args.vbus, "-n", "2", "--baud", str(args.baud), "--link-dir",
                                 links])
        procs.append(vbus)
        wait_for(lambda: os.path.exists(os.path.join(links, "ep1")), 10, "the virtual bus")
        recording = os.path.join(work, "soak.pcapng")
        events = os.path.join(work, "events.jsonl")
        live = subprocess.Popen([args.rtuscope, "live", os.path.join(links, "ep1"), "--baud",
                                 str(args.baud), "--format", "jsonl", "-o", os.devnull,
                                 "-w", recording, "--rotate", args.rotate, "--events", events,
                                 "--summary-every", "5m", "--bus-name", "soak"])
        procs.append(live)
        wait_for(lambda: glob.glob(os.path.join(work, "soak*.pcapng")), 10,
                 "the recording to start")
        player = Player(os.path.join(links, "ep0"), traffic)
        player.start()

        samples = []
        started = time.monotonic()
        print(f"{'minute':>8} {'rss_kb':>8} {'fds':>4} {'cpu_s':>8} {'cpu_%':>6} {'bytes':>10}")
        while True:
            elapsed = time.monotonic() - started
            if live.poll() is not None:
                fail(f"live stopped by itself (exit {live.returncode}) after {elapsed:.0f} s")
            rss, fds, cpu = sample(live.pid)
            cpu_pct = 100 * (cpu - samples[-1][3]) / (elapsed - samples[-1][0]) if samples else 0
            samples.append((elapsed, rss, fds, cpu))
            print(f"{elapsed / 60:8.1f} {rss:8d} {fds:4d} {cpu:8.2f} {cpu_pct:6.2f} "
                  f"{player.written:10d}", flush=True)
            if elapsed >= duration:
                break
            time.sleep(min(interval, max(0.0, duration - elapsed)))

        player.stop()
        time.sleep(1.0)  # the last bytes cross the virtual line
        live.send_signal(signal.SIGTERM)
        if live.wait(timeout=30) != 0:
            fail(f"live exited {live.returncode} on SIGTERM")
    finally:
        for p in reversed(procs):
            if p.poll() is None:
                p.terminate()
                p.wait(timeout=10)

    baseline = [s for s in samples if s[0] <= baseline_window]
    limit = max(s[1] for s in baseline) * RSS_MARGIN
    peak = max(s[1] for s in samples)
    files = sorted(glob.glob(os.path.join(work, "soak*.pcapng")))
    report = subprocess.run([args.rtuscope, "report", "--format", "json", "--no-identify",
                             *files], capture_output=True, text=True, timeout=600)
    if report.returncode != 0:
        fail(f"the recordings do not read back as one capture: {report.stderr}")
    recorded = json.loads(report.stdout)["totals"]["bytes"]
    stop_events = [e for e in map(json.loads, open(events)) if e.get("event") == "stop"]
    summary = {
        "duration_s": round(samples[-1][0]), "samples": len(samples),
        "rss_kb_first": samples[0][1], "rss_kb_baseline_max": max(s[1] for s in baseline),
        "rss_kb_peak": peak, "fds_first": samples[0][2],
        "fds_max": max(s[2] for s in samples), "cpu_s": round(samples[-1][3], 2),
        "cpu_pct_of_core": round(100 * samples[-1][3] / samples[-1][0], 3),
        "files": len(files), "bytes_played": player.written, "bytes_recorded": recorded,
    }
    print(json.dumps(summary))
    if peak > limit:
        fail(f"RSS grew to {peak} kB, over its first-part level plus 10% ({limit:.0f} kB)")
    if summary["fds_max"] > samples[0][2] + FD_MARGIN:
        fail(f"open files grew from {samples[0][2]} to {summary['fds_max']}")
    if recorded != player.written:
        fail(f"{player.written} bytes played, {recorded} in the recordings")
    if len(files) < 2:
        fail(f"rotation made {len(files)} file(s); expected several")
    if not stop_events:
        fail("no stop event at the end of the run")
    print(f"soak: {summary['duration_s']} s, RSS peak {peak} kB (limit {limit:.0f}), "
          f"{len(files)} files, every one of {recorded} bytes recorded")


if __name__ == "__main__":
    main()
