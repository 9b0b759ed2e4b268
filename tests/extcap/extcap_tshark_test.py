#!/usr/bin/env python3
"""`rtuscope extcap` under the real tshark, installed as a user would install it.

  cli      the installed script (the exact file Wireshark runs) answers the extcap calls:
           interfaces (including RTUSCOPE_EXTCAP_PORTS), link types, options; Wireshark's
           extra arguments are accepted; a wrong interface is a clear error.
  capture  a temporary HOME gets tools/install-extcap.sh; `tshark -D` lists the virtual
           bus's endpoint; `tshark -i <iface> -o extcap.<iface>.baud:... -a duration:N`
           captures the demo's traffic played on the bus while `rtuscope live` decodes the
           same traffic on another endpoint: tshark's frames (unit, function code, noise,
           comments) equal rtuscope's records. Then the raw link type: tshark gets the reads
           as RTAC Serial records holding every byte played. The extcap is gone after each
           capture and said nothing on stderr.
"""
import argparse
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.realpath(__file__))
sys.path.insert(0, os.path.join(HERE, "../live"))
from bus_helpers import fail, open_endpoint, stop_all  # noqa: E402

BAUD = 9600


def start_bus(vbus, n):
    proc = subprocess.Popen([vbus, "-n", str(n), "--baud", str(BAUD), "--parity", "E"],
                            stdout=subprocess.PIPE, text=True)
    return proc, [proc.stdout.readline().strip() for _ in range(n)]


def install(source, rtuscope, home):
    env = dict(os.environ, HOME=home)
    env.pop("WIRESHARK_CONFIG_DIR", None)
    r = subprocess.run([os.path.join(source, "tools", "install-extcap.sh"), rtuscope], env=env,
                       capture_output=True, text=True, timeout=30)
    if r.returncode != 0:
        fail(f"install-extcap.sh exited {r.returncode}: {r.stderr}")
    script = os.path.join(home, ".config", "wireshark", "extcap", "rtuscope-extcap")
    if not os.access(script, os.X_OK):
        fail(f"install-extcap.sh did not install {script}: {r.stdout}")
    return script, env


def run(cmd, env, timeout=30):
    return subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)


def pref_name(interface):
    """Wireshark's preference prefix of an extcap interface (FORMATS §10.3)."""
    return "extcap." + re.sub(r"[^A-Za-z0-9_]", "_", interface).lower()


def cli(args, work):
    home = os.path.join(work, "home")
    script, env = install(args.source, args.rtuscope, home)
    env["RTUSCOPE_EXTCAP_PORTS"] = "/dev/pts/nonexistent-a:relative/port"
    r = run([script, "--extcap-interfaces", "--extcap-version=4.0", "--some-future-arg", "x"],
            env)
    if r.returncode != 0 or r.stderr:
        fail(f"--extcap-interfaces: exit {r.returncode}: {r.stderr}")
    lines = r.stdout.splitlines()
    if not lines or not re.fullmatch(r"extcap \{version=[0-9.]+\}", lines[0]):
        fail(f"--extcap-interfaces: first line {lines[:1]}")
    relative = os.path.join(os.getcwd(), "relative", "port")
    for port in ("/dev/pts/nonexistent-a", relative):
        want = f"interface {{value=rtuscope{port}}}{{display=Modbus RTU on {port} (rtuscope)}}"
        if want not in lines:
            fail(f"--extcap-interfaces does not list {port}:\n{r.stdout}")
    iface = "rtuscope/dev/pts/nonexistent-a"
    r = run([script, "--extcap-dlts", "--extcap-interface", iface], env)
    if r.returncode != 0 or [l.split("}")[0] for l in r.stdout.splitlines()] != \
            ["dlt {number=252", "dlt {number=250"]:
        fail(f"--extcap-dlts: exit {r.returncode}: {r.stdout} {r.stderr}")
    r = run([script, "--extcap-config", "--extcap-interface", iface, "--extcap-reload-option",
             "baud"], env)
    calls = re.findall(r"\{call=([^}]*)\}", r.stdout)
    if r.returncode != 0 or calls != ["--baud", "--parity", "--stop", "--timeout-ms", "--bus",
                                      "--link-type"]:
        fail(f"--extcap-config: exit {r.returncode}, calls {calls}: {r.stderr}")
    r = run([script, "--extcap-config", "--extcap-interface", "eth0"], env)
    if r.returncode != 2 or "eth0" not in r.stderr:
        fail(f"a foreign interface: exit {r.returncode}: {r.stderr}")
    r = run([script], env)
    if r.returncode != 2 or "--extcap-interfaces" not in r.stderr:
        fail(f"no extcap call: exit {r.returncode}: {r.stderr}")
    # A port that does not open: the FIFO is opened first, so tshark ends at once with the
    # reason instead of waiting for a capture that never starts.
    started = time.monotonic()
    r = run([args.tshark, "-i", iface, "-a", "duration:20"], env, timeout=60)
    took = time.monotonic() - started
    if took > 10 or "Error by extcap pipe" not in r.stderr or \
            "/dev/pts/nonexistent-a: " not in r.stderr:
        fail(f"tshark on a missing port took {took:.1f} s, said: {r.stderr}")
    print(f"OK: {script} lists the ports, 2 link types, {len(calls)} options; bad calls exit 2; "
          f"a missing port ends tshark's capture in {took:.1f} s with the reason")


def demo_bursts(source):
    """The demo's traffic as (start time s, bytes) bursts: bytes closer than 1.5 characters
    belong together (the hex capture holds one byte per line, time = its end)."""
    char = 11.0 / BAUD
    bursts = []
    with open(os.path.join(source, "captures", "demo_four_devices.hex")) as f:
        for line in f:
            if not line.strip() or line.startswith("#"):
                continue
            t, byte = line.split()
            t = float(t)
            if bursts and t - bursts[-1][2] < 1.5 * char:
                bursts[-1][1].append(int(byte, 16))
                bursts[-1][2] = t
            else:
                bursts.append([t - char, [int(byte, 16)], t])
    return [(start, bytes(data)) for start, data, _ in bursts]


def play(path, bursts):
    fd = open_endpoint(path)
    try:
        t0 = time.monotonic() - bursts[0][0]
        for start, data in bursts:
            delay = t0 + start - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            os.write(fd, data)
        time.sleep(1.0)  # the last frame crosses the line and is decided
    finally:
        os.close(fd)


def extcap_pids(port):
    """Processes running the extcap with `port` open."""
    pids = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            cmdline = open(f"/proc/{pid}/cmdline", "rb").read().split(b"\0")
            if b"extcap" not in cmdline and b"--capture" not in cmdline:
                continue
            fds = os.listdir(f"/proc/{pid}/fd")
            if any(os.readlink(f"/proc/{pid}/fd/{fd}") == port for fd in fds):
                pids.append(int(pid))
        except OSError:
            continue
    return pids


def wait_for(predicate, what, deadline=15.0):
    end = time.monotonic() + deadline
    while time.monotonic() < end:
        if predicate():
            return
        time.sleep(0.05)
    fail(f"timed out waiting until {what}")


def tshark_capture(args, env, iface, port, fields, extra_prefs, duration, bursts):
    prefs = [f"{pref_name(iface)}.baud:{BAUD}", f"{pref_name(iface)}.parity:E"] + extra_prefs
    cmd = [args.tshark, "-i", iface, "-a", f"duration:{duration}", "-T", "fields",
           "-E", "occurrence=f"]
    for p in prefs:
        cmd += ["-o", p]
    for f in fields:
        cmd += ["-e", f]
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    try:
        wait_for(lambda: extcap_pids(port) or proc.poll() is not None,
                 f"the extcap opened {port}")
        if proc.poll() is not None:
            fail(f"tshark ended early: {proc.communicate()[1]}")
        if bursts:
            play(args.player_port, bursts)
        out, err = proc.communicate(timeout=duration + 30)
    finally:
        stop_all([proc])
    if proc.returncode != 0:
        fail(f"tshark exited {proc.returncode}: {err}")
    # A normal stop prints an empty "tshark: " line; anything the extcap says is an error.
    if "Error by extcap pipe" in err or "rtuscope extcap" in err:
        fail(f"tshark reported the extcap's stderr: {err}")
    wait_for(lambda: not extcap_pids(port), "the extcap ended after the capture", 5.0)
    return [line.split("\t") for line in out.splitlines()]


def capture(args, work):
    home = os.path.join(work, "home")
    _, env = install(args.source, args.rtuscope, home)
    bus, ports = start_bus(args.vbus, 3)
    procs = [bus]
    try:
        player, extcap_port, live_port = ports
        args.player_port = player
        env["RTUSCOPE_EXTCAP_PORTS"] = extcap_port
        iface = "rtuscope" + extcap_port
        r = run([args.tshark, "-D"], env)
        if r.returncode != 0 or not any(line.split(". ", 1)[-1].startswith(iface + " ")
                                        for line in r.stdout.splitlines()):
            fail(f"tshark -D does not list {iface}: {r.stdout} {r.stderr}")

        live_out = os.path.join(work, "live.jsonl")
        with open(live_out, "w") as out:
            live = subprocess.Popen([args.rtuscope, "live", live_port, "--baud", str(BAUD),
                                     "--parity", "E", "--format", "jsonl"], stdout=out,
                                    stderr=subprocess.PIPE, text=True)
        procs.append(live)
        line = live.stderr.readline()
        while line and "listening on" not in line:
            line = live.stderr.readline()
        if not line:
            fail("rtuscope live did not start listening")

        bursts = demo_bursts(args.source)
        started = time.monotonic()
        rows = tshark_capture(args, env, iface, extcap_port,
                              ["mbrtu.unit_id", "modbus.func_code", "frame.comment",
                               "frame.interface_name"],
                              ["mbrtu.tcp.port:502"], 14, bursts)
        took = time.monotonic() - started
        live.send_signal(signal.SIGINT)
        live.wait(timeout=10)
        with open(live_out) as f:
            records = [json.loads(l) for l in f if l.strip()]
        records = [r for r in records if r["kind"] in ("frame", "noise")]
        if len(records) < 100:
            fail(f"rtuscope live decoded only {len(records)} records of the demo traffic")
        if len(rows) != len(records):
            fail(f"tshark got {len(rows)} packets, rtuscope live decoded {len(records)} records")
        if any(row[3] != extcap_port for row in rows):  # the IDB names the port
            fail(f"packets not from {extcap_port}: {rows[:3]}")

        def decodable(r):  # what Wireshark's mbrtu dissects (FORMATS §3.2)
            return r["kind"] == "frame" and r["slave"] != 0 and len(r["hex"].replace(" ", "")) >= 10

        frames = [r for r in records if decodable(r)]
        got = [(row[0], row[1]) for row in rows if row[0]]
        if [unit for unit, _ in got] != [str(r["slave"]) for r in frames]:
            fail(f"tshark decoded {len(got)} Modbus RTU frames, rtuscope {len(frames)}; "
                 "their units differ")
        # Wireshark's dissector gives up on a broken frame (a cut-off response) after the
        # unit id; rtuscope found an issue on every such frame.
        for (unit, fc), r in zip(got, frames):
            if fc == "" and not r.get("issues"):
                fail(f"tshark found no function code in a frame rtuscope found sound: {r}")
            if fc != "" and fc != str(r["fc"] & 0x7F):
                fail(f"tshark reads function {fc}, rtuscope {r['fc']}: {r}")
        same_fc = sum(1 for _, fc in got if fc)
        if same_fc < len(got) * 0.9:
            fail(f"only {same_fc} of {len(got)} frames have a function code in tshark")
        crc_comments = sum(1 for row in rows if "crc:" in row[2])
        crc_records = sum(1 for r in records if "crc" in (r.get("issues") or []))
        if crc_comments != crc_records or crc_records == 0:
            fail(f"{crc_comments} packets say crc in their comment, rtuscope found {crc_records}")
        print(f"OK: tshark captured {len(rows)} packets live in {took:.1f} s, {len(got)} decoded "
              f"as Modbus RTU with the same unit as `rtuscope live` ({same_fc} with the same "
              f"function, the rest cut off), "
              f"{crc_comments} with a CRC comment")

        # The raw link type: reads and line events, every byte played.
        raw = tshark_capture(args, env, iface, extcap_port, ["rtacser.eventtype", "data.data"],
                             [f"{pref_name(iface)}.linktype:raw"], 4,
                             [(0.0, bytes([1, 3, 0, 0, 0, 1, 0x84, 0x0A])),
                              (0.05, bytes([1, 3, 2, 0, 42, 0x38, 0x5B]))])
        played = "01030000000184" "0a" "010302002a385b"
        got_bytes = "".join(row[1].replace(":", "") for row in raw if len(row) > 1)
        if got_bytes != played:
            fail(f"raw capture holds {got_bytes!r}, the bus carried {played!r}: {raw}")
        print(f"OK: raw link type: {len(raw)} RTAC Serial records holding the {len(played) // 2} "
              "bytes played")
    finally:
        stop_all(procs)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--vbus", required=True)
    ap.add_argument("--tshark", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--scenario", choices=["cli", "capture"], required=True)
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="rtuscope_extcap_")
    try:
        {"cli": cli, "capture": capture}[args.scenario](args, work)
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
