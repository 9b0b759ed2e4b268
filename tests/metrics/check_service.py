#!/usr/bin/env python3
"""Service mode: `rtuscope live --bus FILE` alone, as tools/systemd/rtuscope@.service runs it.

On a virtual bus (rtuvbus), a bus file whose [live] section names the port, the recording,
the metrics address, the event log and the bus name starts a full session with no other
option. Frames written on the bus show in /metrics under the file's bus name; SIGHUP starts a
new capture file; SIGTERM ends the run cleanly (exit 0, a `stop` event, a readable recording).
The shipped examples (three buses, their scrape config) must load too.
"""
import argparse
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import tty
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail  # noqa: E402  (after the path line)
from modbus_crc import with_crc  # noqa: E402


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def metric(text, name):
    return sum(float(v) for v in re.findall(rf"^{name}{{[^}}]*}} (\S+)$", text, re.M))


def check_examples(args, work):
    """The shipped bus files load: live fails on their (absent) port, not on the file. The
    files' paths and addresses are the plant's: the command line overrides them here."""
    examples = os.path.join(args.source, "tools", "systemd", "examples")
    buses = sorted(f for f in os.listdir(examples) if f.endswith(".toml"))
    if len(buses) < 3:
        fail(f"expected three example buses, found {buses}")
    for name in buses:
        out = subprocess.run([args.rtuscope, "live", "--bus", os.path.join(examples, name),
                              "--duration", "0.1", "--metrics", "127.0.0.1:0",
                              "--events", os.path.join(work, "events.jsonl"),
                              "-w", os.path.join(work, "example.pcapng")],
                             capture_output=True, text=True, timeout=30)
        if out.returncode != 2 or "no such serial port" not in out.stderr or ".toml" in out.stderr:
            fail(f"{name}: expected only its port to fail, got {out.returncode}: {out.stderr}")
    # The scrape config, with its rule file pointing at the shipped rules.
    config = open(os.path.join(examples, "prometheus.yml")).read().replace(
        "/etc/prometheus/rtuscope.rules.yml",
        os.path.abspath(os.path.join(args.source, "tools", "prometheus", "rtuscope.rules.yml")))
    path = os.path.join(work, "prometheus.yml")
    open(path, "w").write(config)
    check = subprocess.run([args.promtool, "check", "config", path], capture_output=True,
                           text=True, timeout=30)
    if check.returncode != 0:
        fail(f"example scrape config: {check.stdout}{check.stderr}")
    unit = open(os.path.join(args.source, "tools", "systemd", "rtuscope@.service")).read()
    if "live --bus /etc/rtuscope/%i.toml" not in unit or "ExecReload=/bin/kill -HUP" not in unit:
        fail("the unit must start `live --bus /etc/rtuscope/%i.toml` and reload with SIGHUP")
    print(f"examples: {len(buses)} bus files load, the scrape config is valid")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--vbus", required=True)
    ap.add_argument("--promtool", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--work", required=True)
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    work = tempfile.mkdtemp(dir=args.work)
    procs = []
    try:
        check_examples(args, work)
        vbus = subprocess.Popen([args.vbus, "-n", "2", "--baud", "19200", "--parity", "N",
                                 "--log", os.path.join(work, "bus.log")],
                                stdout=subprocess.PIPE, text=True)
        procs.append(vbus)
        master, sniff = [vbus.stdout.readline().strip() for _ in range(2)]
        port = free_port()
        recording = os.path.join(work, "line.pcapng")
        events = os.path.join(work, "events.jsonl")
        bus_file = os.path.join(work, "line.toml")
        with open(bus_file, "w") as f:
            f.write(f'[line]\nbaud = 19200\nparity = "N"\n\n[live]\nport = "{sniff}"\n'
                    f'bus_name = "line-9"\nwrite = "{recording}"\n'
                    f'metrics = "127.0.0.1:{port}"\nevents = "{events}"\n')
        err_path = os.path.join(work, "err.txt")
        with open(err_path, "w") as err:
            live = subprocess.Popen([args.rtuscope, "live", "--bus", bus_file],
                                    stdout=subprocess.DEVNULL, stderr=err)
        procs.append(live)
        stderr = lambda: open(err_path).read()
        deadline = time.monotonic() + 20
        while "serving metrics on" not in stderr():
            if time.monotonic() > deadline or live.poll() is not None:
                fail(f"live --bus did not start: {stderr()}")
            time.sleep(0.1)

        fd = os.open(master, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(fd)
        requests = 5
        for i in range(requests):
            os.write(fd, with_crc(bytes([7, 3, 0, i, 0, 1])))
            time.sleep(0.05)
        os.close(fd)

        url = f"http://127.0.0.1:{port}/metrics"
        deadline = time.monotonic() + 15
        while True:
            text = urllib.request.urlopen(url, timeout=5).read().decode()
            if metric(text, "rtuscope_frames_total") >= requests:
                break
            if time.monotonic() > deadline:
                fail(f"frames never reached {requests} in /metrics:\n{text[:2000]}")
            time.sleep(0.2)
        if 'rtuscope_frames_total{bus="line-9"}' not in text:
            fail("the bus file's bus_name does not label the metrics")
        if metric(text, "rtuscope_requests_total") != requests:
            fail(f"requests: {metric(text, 'rtuscope_requests_total')}, sent {requests}")

        os.rename(recording, recording + ".1")
        live.send_signal(signal.SIGHUP)
        deadline = time.monotonic() + 10
        while "SIGHUP: recording on in" not in stderr():
            if time.monotonic() > deadline or live.poll() is not None:
                fail(f"no new recording after SIGHUP: {stderr()}")
            time.sleep(0.1)
        live.send_signal(signal.SIGTERM)
        if live.wait(timeout=20) != 0:
            fail(f"live exited {live.returncode} on SIGTERM: {stderr()}")
        kinds = [json.loads(line)["event"] for line in open(events)]
        if kinds[0] != "start" or kinds[-1] != "stop" or "rotation" not in kinds:
            fail(f"events {kinds}: expected start, a rotation, stop")
        decoded = subprocess.run([args.rtuscope, "decode", "--format", "jsonl",
                                  recording + ".1", recording],
                                 capture_output=True, text=True, timeout=30)
        frames = sum(1 for line in decoded.stdout.splitlines()
                     if line.strip() and json.loads(line).get("kind") == "frame")
        if decoded.returncode != 0 or frames != requests:
            fail(f"the recording decodes to {frames} frames ({decoded.stderr}), sent {requests}")
        # The recording names its bus in the interface description, as Wireshark shows it.
        with open(recording, "rb") as f:
            if b"; bus line-9" not in f.read():
                fail("the recording's interface description does not name the bus line-9")
        print(f"live --bus alone: {requests} frames in /metrics and in the recording, "
              f"SIGHUP rotated, events {kinds}")
        print("passed")
    finally:
        for p in reversed(procs):
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
                try:
                    p.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
