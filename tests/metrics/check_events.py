#!/usr/bin/env python3
"""`--events`, `--summary-every` and SIGHUP on `rtuscope demo` (the live session's code).

The demo runs with an event log, a summary every 2 s and a recording. Midway the recording
and the event log are moved away and rtuscope gets SIGHUP (as logrotate does it). Checks:
  * the event log is appended to (a line of an earlier run is kept), and after SIGHUP it
    goes on in a new file at its path;
  * every line is one JSON object with time, bus and event first, and uses only keys that
    src/report/events.def declares;
  * timeouts and exceptions in the events equal the report's, slave by slave; every finding
    of the report was an event;
  * summaries came as events and as comments in the recording (tshark), and after SIGHUP the
    recording went on in a new file, announced as a `rotation` event;
  * the two files, read as one capture, decode to the report's frames: the comments and the
    new section change nothing in a replay.
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
from collections import Counter

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail  # noqa: E402  (after the path line)


def declared_keys(events_def):
    text = open(events_def).read()
    events = set(re.findall(r'^RTU_EVENT\(\s*\w+,\s*"([^"]+)"', text, re.M))
    fields = set(re.findall(r'^RTU_EVENT_FIELD\(\s*\w+,\s*"([^"]+)"', text, re.M))
    if not events or not fields:
        fail(f"no keys found in {events_def}")
    return events, fields


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--work", required=True)
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    work = tempfile.mkdtemp(dir=args.work)
    demo = None
    try:
        events_path = os.path.join(work, "events.jsonl")
        events_moved = os.path.join(work, "events-old.jsonl")
        # A restarted service appends to the log it finds.
        earlier = '{"time":"2026-01-01T00:00:00.000000Z","bus":"line-7","event":"stop"}\n'
        with open(events_path, "w") as f:
            f.write(earlier)
        report_path = os.path.join(work, "report.json")
        capture = os.path.join(work, "bus.pcapng")
        moved = os.path.join(work, "bus-old.pcapng")
        err_path = os.path.join(work, "err.txt")
        started = time.time()
        with open(err_path, "w") as err:
            demo = subprocess.Popen(
                [args.rtuscope, "demo", "--events", events_path, "--summary-every", "2s",
                 "-w", capture, "--report", report_path, "--bus-name", "line-7"],
                stdout=subprocess.DEVNULL, stderr=err)
        # Midway (the traffic lasts about 7 s): rotate as logrotate would.
        deadline = time.monotonic() + 20
        while not os.path.exists(capture) or os.path.getsize(capture) < 2000:
            if time.monotonic() > deadline or demo.poll() is not None:
                fail("the recording did not grow")
            time.sleep(0.1)
        os.rename(capture, moved)
        os.rename(events_path, events_moved)
        demo.send_signal(signal.SIGHUP)
        if demo.wait(timeout=60) != 0:
            fail(f"demo exited {demo.returncode}: {open(err_path).read()}")
        demo = None
        ended = time.time()

        event_keys, field_keys = declared_keys(
            os.path.join(args.source, "src", "report", "events.def"))
        before_hangup = open(events_moved).read()
        if not before_hangup.startswith(earlier) or not os.path.exists(events_path):
            fail("the event log must be appended to, and opened again at its path on SIGHUP")
        after_hangup = open(events_path).read()
        if not after_hangup or '"event":"start"' in after_hangup:
            fail("after SIGHUP the events must go on in a new file at the same path")
        events = []
        lines = (before_hangup[len(earlier):] + after_hangup).splitlines()
        for n, line in enumerate(lines, 1):
            e = json.loads(line)
            if list(e)[:3] != ["time", "bus", "event"]:
                fail(f"line {n}: time, bus and event must come first: {line}")
            if e["event"] not in event_keys:
                fail(f"line {n}: event {e['event']} is not declared in events.def")
            undeclared = set(e) - field_keys
            if undeclared:
                fail(f"line {n}: keys {undeclared} are not declared in events.def")
            if e["bus"] != "line-7":
                fail(f"line {n}: bus {e['bus']}")
            m = re.fullmatch(r"(\d{4})-(\d\d)-(\d\d)T(\d\d):(\d\d):(\d\d\.\d{6})Z", e["time"])
            if not m:
                fail(f"line {n}: time {e['time']} is not ISO 8601 UTC")
            t = time.mktime(time.strptime(e["time"][:19], "%Y-%m-%dT%H:%M:%S")) - time.timezone
            if not started - 2 <= t <= ended + 2:
                fail(f"line {n}: time {e['time']} is outside the run")
            events.append(e)
        kinds = Counter(e["event"] for e in events)
        print("events:", dict(kinds))
        if events[0]["event"] != "start" or events[-1]["event"] != "stop":
            fail("the log must open with start and close with stop")

        report = json.load(open(report_path))
        totals, slaves = report["totals"], report["slaves"]
        by_slave = lambda kind: Counter(str(e["slave"]) for e in events if e["event"] == kind)
        want_timeouts = {s: v["timeouts"] for s, v in slaves.items() if v["timeouts"]}
        want_exceptions = {s: v["exceptions"] for s, v in slaves.items() if v["exceptions"]}
        if dict(by_slave("timeout")) != want_timeouts or totals["timeouts"] == 0:
            fail(f"timeouts: events {dict(by_slave('timeout'))}, report {want_timeouts}")
        if dict(by_slave("exception")) != want_exceptions or totals["exceptions"] == 0:
            fail(f"exceptions: events {dict(by_slave('exception'))}, report {want_exceptions}")
        found = {(e["key"], e["slave"]) for e in events if e["event"] == "finding"}
        reported = {(f["key"], f.get("slave")) for f in report["findings"]}
        if not reported or not reported <= found:
            fail(f"findings of the report missing from the events: {reported - found}")

        summaries = [e for e in events if e["event"] == "summary"]
        if len(summaries) < 2:
            fail(f"{len(summaries)} summaries in a run of over 6 s at one per 2 s")
        if sum(s["frames"] for s in summaries) > totals["frames"]:
            fail("the summaries count more frames than the run had")
        rotations = [e for e in events if e["event"] == "rotation"]
        if [r["file"] for r in rotations] != [capture]:
            fail(f"rotation events {rotations}, expected one for {capture}")
        if not os.path.exists(capture):
            fail("no new file after SIGHUP")

        comments = []
        for path in (moved, capture):
            out = subprocess.run(["tshark", "-r", path, "-Y", "frame.comment", "-T", "fields",
                                  "-e", "frame.comment"], capture_output=True, text=True,
                                 timeout=60)
            comments += [c for c in out.stdout.splitlines() if c.startswith("rtuscope summary")]
        if sorted(comments) != sorted(s["summary"] for s in summaries):
            fail(f"capture comments {comments} differ from the summary events")

        decoded = subprocess.run([args.rtuscope, "decode", "--format", "jsonl", moved, capture],
                                 capture_output=True, text=True, timeout=60)
        if decoded.returncode != 0:
            fail(f"decode of the two files: {decoded.stderr}")
        frames = sum(1 for line in decoded.stdout.splitlines()
                     if line.strip() and json.loads(line).get("kind") == "frame")
        print(f"frames: report {totals['frames']}, decode of the two files {frames}; "
              f"{len(summaries)} summaries, {len(comments)} comments")
        if frames != totals["frames"]:
            fail(f"the recording decodes to {frames} frames, the report counted {totals['frames']}")
        print("passed")
    finally:
        if demo is not None and demo.poll() is None:
            demo.kill()
            demo.wait()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
