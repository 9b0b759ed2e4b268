#!/usr/bin/env python3
"""`rtuscope demo --mqtt` against the real Mosquitto broker from Debian.

  discovery  a broker on a free loopback port, `mosquitto_sub` collecting everything, the
             demo with --mqtt and --mqtt-discovery: every point published has a retained Home
             Assistant config whose device_class/state_class are those its device map states,
             else those the data file gives for its unit (the YW2050's power factors and the
             TH900's RH say their own); the last value of every point equals the last value the demo
             decoded; slaves 1-4 are online; the CRC faults are findings; the last health
             message counts the demo's frames; rtuscope's own status ends "offline".
  restart    the demo starts before the broker, which is then started, stopped mid-run and
             started again: the demo decodes the traffic exactly as without a broker, says
             it could not connect, was connected, lost the connection and got it back; values
             reach a subscriber after the restart, and the messages dropped from the small
             queue are counted.
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
import tomllib

HERE = os.path.dirname(os.path.realpath(__file__))
sys.path.insert(0, os.path.join(HERE, "../live"))
from bus_helpers import fail, stop_all  # noqa: E402


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_broker(work, port):
    conf = os.path.join(work, "broker.conf")
    with open(conf, "w") as f:
        f.write(f"listener {port} 127.0.0.1\nallow_anonymous true\npersistence false\n")
    log = open(os.path.join(work, "broker.log"), "a")
    broker = subprocess.Popen(["mosquitto", "-c", conf], stdout=log, stderr=log)
    wait_port(port, broker)
    return broker


def wait_port(port, proc, deadline=10.0):
    end = time.monotonic() + deadline
    while time.monotonic() < end:
        if proc.poll() is not None:
            fail(f"mosquitto exited {proc.returncode}")
        try:
            socket.create_connection(("127.0.0.1", port), timeout=0.2).close()
            return
        except OSError:
            time.sleep(0.05)
    fail(f"mosquitto is not listening on {port}")


def start_subscriber(port, out_path, topics=("rtuscope/#", "homeassistant/#")):
    cmd = ["mosquitto_sub", "-h", "127.0.0.1", "-p", str(port), "-F", "%r %t %p"]
    for t in topics:
        cmd += ["-t", t]
    sub = subprocess.Popen(cmd, stdout=open(out_path, "w"), stderr=subprocess.STDOUT)
    time.sleep(0.3)  # subscribed before anything is published
    return sub


def messages(path):
    out = []
    with open(path) as f:
        for line in f:
            retain, topic, payload = line.rstrip("\n").split(" ", 2)
            out.append((retain == "1", topic, payload))
    return out


def retained(port):
    """What a late subscriber gets: the retained messages, by topic."""
    r = subprocess.run(["mosquitto_sub", "-h", "127.0.0.1", "-p", str(port), "-t", "#",
                        "--retained-only", "-W", "2", "-F", "%t %p"],
                       capture_output=True, text=True, timeout=20)
    return dict(line.split(" ", 1) for line in r.stdout.splitlines() if " " in line)


def jsonl(text):
    return [json.loads(line) for line in text.splitlines() if line.strip()]


def mqtt_id(name):
    """A point name as topics and Home Assistant ids hold it (report/mqtt_feed.hpp)."""
    return re.sub(r"[^A-Za-z0-9_-]", "_", name)


def decoded_points(records):
    """(slave, point id) → last value the demo decoded: a read's values are on its sound
    response, a write's on its request once a sound response confirms it."""
    last = {}
    requests = {}
    for r in records:
        if r.get("kind") != "frame":
            continue
        if r.get("role") == "request":
            requests[r.get("txn")] = r
            continue
        request = requests.get(r.get("txn"))
        if r.get("role") != "response" or not r.get("crc_ok") or r["fc"] & 0x80 or \
                request is None or not request.get("crc_ok") or request["fc"] != r["fc"]:
            continue
        regs = (r.get("registers") or []) + (request.get("registers") or [] if r["fc"] in (5, 6, 15, 16) else [])
        for reg in regs:
            if reg.get("value") is not None and "name" in reg:
                last[(r["slave"], mqtt_id(reg["name"]))] = reg["value"]
    return last


def map_classes(source):
    """(slave, point id) → the Home Assistant classes the demo's device maps state for the
    point ("" = none), for the keys they state."""
    with open(os.path.join(source, "captures", "demo_four_devices.bus.toml"), "rb") as f:
        slaves = tomllib.load(f)["slaves"]
    out = {}
    for slave, model in slaves.items():
        with open(os.path.join(source, "dissectors", f"{model}.toml"), "rb") as f:
            device_map = tomllib.load(f)
        for space in device_map["space"].values():
            for point in space.get("point", []):
                stated = {k: point[k] for k in ("device_class", "state_class") if k in point}
                if stated:
                    out[(int(slave), mqtt_id(point["name"]))] = stated
    return out


def discovery(args, work):
    port = free_port()
    procs = [start_broker(work, port)]
    try:
        sub_path = os.path.join(work, "sub.txt")
        procs.append(start_subscriber(port, sub_path))
        demo = subprocess.run([args.rtuscope, "demo", "--format", "jsonl", "--mqtt",
                               f"mqtt://127.0.0.1:{port}", "--mqtt-discovery"],
                              capture_output=True, text=True, timeout=60)
        if demo.returncode != 0:
            fail(f"demo exited {demo.returncode}: {demo.stderr}")
        time.sleep(0.5)
        late = retained(port)
    finally:
        stop_all(procs)
    msgs = messages(sub_path)
    records = jsonl(demo.stdout)
    with open(os.path.join(args.source, "dissectors", "home_assistant",
                           "sensor_classes.toml"), "rb") as f:
        classes = tomllib.load(f)["unit"]
    stated = map_classes(args.source)
    # The points whose maps say their classes, as Home Assistant must get them.
    annotated = {(1, "PFa"): {"device_class": "power_factor", "state_class": "measurement"},
                 (3, "RH"): {"device_class": "humidity", "state_class": "measurement"}}

    values = {}
    for _, topic, payload in msgs:
        parts = topic.split("/")
        if parts[0] == "rtuscope" and len(parts) == 4 and parts[3] != "status":
            values[(int(parts[2]), parts[3])] = json.loads(payload)
    want = decoded_points(records)
    if not want:
        fail("the demo decoded no named points")
    for key in annotated:
        if key not in want:
            fail(f"the demo decoded no {key}, whose map states its classes")
    if set(values) != set(want):
        fail(f"points only published: {sorted(set(values) - set(want))[:5]}, only decoded: "
             f"{sorted(set(want) - set(values))[:5]}")
    for key, v in values.items():
        if abs(v["value"] - want[key]) > 1e-9 * max(1.0, abs(want[key])):
            fail(f"{key}: last published {v['value']}, last decoded {want[key]}")
        if "model" not in v or "time" not in v or "unit" not in v:
            fail(f"{key}: {v}")

    configs = {t: json.loads(p) for t, p in late.items() if t.startswith("homeassistant/")}
    classed = 0
    own = 0
    for (slave, point), v in values.items():
        topic = f"homeassistant/sensor/rtuscope_demo_{slave}/{point}/config"
        if topic not in configs:
            fail(f"no retained discovery config {topic}")
        config = configs[topic]
        if config["state_topic"] != f"rtuscope/demo/{slave}/{point}" or \
                config["device"]["identifiers"] != [f"rtuscope_demo_{slave}"]:
            fail(f"{topic}: {config}")
        unit = v["unit"]
        expected = {k: c for k, c in {**classes.get(unit, {}),
                                      **stated.get((slave, point), {})}.items() if c}
        if config.get("device_class") != expected.get("device_class") or \
                config.get("state_class") != expected.get("state_class") or \
                config.get("unit_of_measurement") != (unit or None):
            fail(f"{topic} for unit {unit!r} (expected {expected}): {config}")
        if (slave, point) in annotated and \
                {k: config.get(k) for k in annotated[(slave, point)]} != annotated[(slave, point)]:
            fail(f"{topic}: {config}, not the classes its map states")
        classed += "device_class" in config
        own += (slave, point) in stated
    if classed == 0:
        fail("no config carries a device_class")

    for slave in (1, 2, 3, 4):
        if late.get(f"rtuscope/demo/{slave}/status") != "online":
            fail(f"slave {slave}'s retained status: {late.get(f'rtuscope/demo/{slave}/status')}")
    if late.get("rtuscope/demo/status") != "offline":
        fail(f"rtuscope's own status after the run: {late.get('rtuscope/demo/status')}")
    findings = [json.loads(p) for _, t, p in msgs if t == "rtuscope/demo/findings"]
    if not any(f["issue"] == "crc" and f["slave"] == 1 for f in findings):
        fail(f"no crc finding on slave 1: {findings}")
    health = [json.loads(p) for _, t, p in msgs if t == "rtuscope/demo/health"]
    frames = sum(1 for r in records if r.get("kind") == "frame")
    if not health or health[-1]["frames"] != frames or health[-1]["mqtt_dropped"] != 0:
        fail(f"last health {health[-1:]} (the demo printed {frames} frames)")
    print(f"OK: {len(msgs)} messages; {len(values)} points equal the decoded values, each with "
          f"a retained config ({classed} with a device_class, {own} with its map's own "
          f"classes); 4 slaves online, "
          f"{len(findings)} findings, health counts {frames} frames")


def restart(args, work):
    port = free_port()
    procs = []
    try:
        # 3 × 6 s of traffic: time for the starter's and the loop's back-offs (1, 2, 4 s).
        demo = subprocess.Popen([args.rtuscope, "demo", "--format", "jsonl", "--repeat", "3",
                                 "--mqtt", f"mqtt://127.0.0.1:{port}", "--mqtt-queue", "40"],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        procs.append(demo)
        time.sleep(1.0)
        broker = start_broker(work, port)
        procs.append(broker)
        time.sleep(3.5)
        broker.send_signal(signal.SIGTERM)
        broker.wait(timeout=10)
        time.sleep(3.0)  # the demo goes on; its queue overflows
        restarted = time.time()
        broker = start_broker(work, port)
        procs.append(broker)
        sub_path = os.path.join(work, "after.txt")
        procs.append(start_subscriber(port, sub_path, ("rtuscope/demo/+/+",)))
        out, err = demo.communicate(timeout=60)
        time.sleep(0.3)
    finally:
        stop_all(procs)
    if demo.returncode != 0:
        fail(f"demo exited {demo.returncode}: {err}")
    traffic = os.path.join(args.source, "captures", "demo_four_devices.hex")
    bus = os.path.join(args.source, "captures", "demo_four_devices.bus.toml")
    decoded = subprocess.run([args.rtuscope, "decode", traffic, "--bus", bus, "--format",
                              "jsonl"], capture_output=True, text=True, timeout=60)
    body = [r["hex"] for r in jsonl(out) if r.get("kind") in ("frame", "noise")]
    want = [r["hex"] for r in jsonl(decoded.stdout) if r.get("kind") in ("frame", "noise")]
    # Every byte played was read and decoded. (On a loaded machine the pseudo-terminals'
    # timing may frame a record or two differently from the file, MQTT or not.)
    if "".join(body) != "".join(want) * 3:
        fail(f"with the broker gone the demo's {len(body)} records hold other bytes than the "
             f"traffic played three times ({3 * len(want)} records)")
    reframed = sum(1 for a, b in zip(body, want * 3) if a != b)
    if reframed > len(body) // 50:
        fail(f"{reframed} of {len(body)} records framed differently from the traffic file")
    for needle in ("mqtt: cannot reach", "mqtt: connection to", "lost",
                   "mqtt: queue full (40 messages)", "messages dropped so far"):
        if needle not in err:
            fail(f"the demo did not say '{needle}': {err}")
    if err.count("mqtt: connected to") != 2:
        fail(f"the demo did not reconnect: {err}")
    summary = [l for l in err.splitlines() if "messages published," in l]
    dropped = int(summary[-1].split(", ")[1].split()[0]) if summary else 0
    if dropped == 0:
        fail(f"no dropped messages counted: {summary}")
    after = [json.loads(p) for _, t, p in messages(sub_path) if not t.endswith("/status")]
    if not after:
        fail("no values reached a subscriber after the broker came back")
    print(f"OK: the demo decoded every byte ({len(body)} records, {reframed} framed otherwise "
          f"than the file) with the broker absent at the start and stopped for 3 s; "
          f"{len(after)} values after the restart; {dropped} messages dropped and counted")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--scenario", choices=["discovery", "restart"], required=True)
    args = ap.parse_args()
    for tool in ("mosquitto", "mosquitto_sub"):
        if shutil.which(tool) is None:
            fail(f"{tool} not found (Debian packages mosquitto, mosquitto-clients)")
    work = tempfile.mkdtemp(prefix="rtuscope_mqtt_")
    os.chmod(work, 0o755)  # the broker drops to user mosquitto and reads its config here
    try:
        {"discovery": discovery, "restart": restart}[args.scenario](args, work)
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
