#!/usr/bin/env python3
"""Runs `rtuscope report` on one capture and checks what a user would rely on.

Options in <capture>.args (--device, --bus, relative to the source tree) are passed on.
Without --browser: the JSON report has every documented key and consistent numbers, the
text report shows the same totals, the HTML report is one self-contained file (no script,
nothing fetched) carrying the same numbers, and --csv writes the header and well-formed
rows. With --browser: Debian's chromium loads the HTML headless, and the DOM it renders
shows the totals computed by the JSON report and a chart for every changing point (named
device points where a slave's model is known); a screenshot is taken and must not be empty.
Exit 77 (skipped) when --browser is given and chromium is not installed.
"""
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail  # noqa: E402  (after the path line)

SLAVE_KEYS = ["device", "requests", "responses", "exceptions", "exceptions_by_code",
              "timeouts", "damaged_requests", "late_responses", "crc_errors", "unsolicited", "wrong_slave",
              "after_next_request", "frames", "bytes", "line_errors", "latency_ms",
              "latency_samples", "latency_unseen", "function_codes", "poll_periods", "timing",
              "timeout_fit"]
TOTAL_KEYS = ["start", "end", "duration_s", "records", "frames", "requests", "responses",
              "broadcasts", "unknown_role", "bytes", "noise_records", "noise_bytes",
              "bus_utilisation_pct", "crc_errors", "exceptions", "timeouts", "damaged_requests",
              "late_responses", "unsolicited", "wrong_slave", "line_errors", "t1_5_pauses", "t3_5_violations",
              "timing_resolution_ms", "slaves", "request_kinds", "request_kinds_overflow",
              "points", "points_overflow"]
FINDING_KEYS = ["key", "severity", "slave", "summary", "cause", "evidence", "units"]


SOURCE_DIR = None  # where the .args paths start


def run(cmd):
    result = subprocess.run(cmd, capture_output=True, text=True, check=False, cwd=SOURCE_DIR)
    if result.returncode != 0:
        fail(f"{' '.join(cmd)} exited {result.returncode}: {result.stderr}")
    return result.stdout


def check_json(report):
    for top in ["capture", "totals", "slaves", "timing", "findings", "timeline", "points"]:
        if top not in report:
            fail(f"JSON report lacks '{top}'")
    totals = report["totals"]
    for key in TOTAL_KEYS:
        if key not in totals:
            fail(f"totals lacks '{key}'")
    if totals["frames"] + totals["noise_records"] != totals["records"]:
        fail("frames + noise records != records")
    if totals["slaves"] != len(report["slaves"]):
        fail("totals.slaves differs from the slaves table")
    requests = 0
    responses = 0
    timeouts = 0
    damaged = 0
    for addr, slave in report["slaves"].items():
        if not addr.isdigit() or not 1 <= int(addr) <= 255:
            fail(f"slave key {addr!r} is not an address")
        for key in SLAVE_KEYS:
            if key not in slave:
                fail(f"slave {addr} lacks '{key}'")
        lat = slave["latency_ms"]
        if lat is not None:
            order = [lat["min"], lat["p50"], lat["p95"], lat["p99"], lat["max"]]
            if order != sorted(order):
                fail(f"slave {addr} latency percentiles out of order: {order}")
        # A latency is either seen (a sample) or hidden in its request's read, never both.
        if slave["latency_samples"] + slave["latency_unseen"] > slave["responses"]:
            fail(f"slave {addr}: {slave['latency_samples']} latencies seen and "
                 f"{slave['latency_unseen']} unseen, of {slave['responses']} responses")
        requests += slave["requests"]
        responses += slave["responses"]
        timeouts += slave["timeouts"]
        damaged += slave["damaged_requests"]
    if requests + totals["broadcasts"] != totals["requests"]:
        fail(f"per-slave requests {requests} + broadcasts != total {totals['requests']}")
    if responses != totals["responses"]:
        fail(f"per-slave responses {responses} != total {totals['responses']}")
    if timeouts != totals["timeouts"] or damaged != totals["damaged_requests"]:
        fail(f"per-slave timeouts/damaged requests {timeouts}/{damaged} != totals "
             f"{totals['timeouts']}/{totals['damaged_requests']}")
    for finding in report["findings"]:
        for key in FINDING_KEYS:
            if key not in finding:
                fail(f"finding lacks '{key}': {finding}")
    timeline = report["timeline"]
    if sum(timeline["frames"]) != totals["frames"]:
        fail("timeline frames do not add up to the total")
    if sum(timeline["timeouts"]) != totals["timeouts"]:
        fail("timeline timeouts do not add up to the total")
    check_noise_finding(report)
    check_glitch_line_errors(report)


def check_glitch_line_errors(report):
    """Line errors on turnaround glitches are a part of the line-error records, and of the
    glitch records of each kind."""
    line_errors = report["totals"]["line_errors"]
    timing = report["timing"]
    flagged = timing["turnaround_glitch"]
    heuristic = timing["turnaround_glitches"]
    if flagged["line_errors"] > flagged["records"] or \
            flagged["from_master_line_errors"] > flagged["from_master"]:
        fail(f"more flagged glitches with line errors than glitches: {flagged}")
    if heuristic["line_errors"] > heuristic["after_requests"] + heuristic["after_responses"]:
        fail(f"more 0x00/0xFF glitches with line errors than glitches: {heuristic}")
    if line_errors["on_turnaround_glitches"] != flagged["line_errors"] + heuristic["line_errors"]:
        fail(f"line errors on glitches {line_errors['on_turnaround_glitches']} != flagged "
             f"{flagged['line_errors']} + 0x00/0xFF {heuristic['line_errors']}")
    if line_errors["on_turnaround_glitches"] > line_errors["records"]:
        fail(f"more line errors on glitches than line-error records: {line_errors}")


def check_noise_finding(report):
    """The noise finding counts bytes and stretches over the same records as the totals:
    never more, and all the totals' bytes when it counts all their records."""
    totals = report["totals"]
    for finding in report["findings"]:
        if finding["key"] != "noise":
            continue
        ev = finding["evidence"]
        if ev["noise_records"] > totals["noise_records"] or \
                ev["noise_bytes"] > totals["noise_bytes"]:
            fail(f"noise finding counts more than the totals: {ev}")
        if ev["noise_records"] == totals["noise_records"] and \
                ev["noise_bytes"] != totals["noise_bytes"]:
            fail(f"noise finding counts all noise records but not all their bytes: {ev}")


def expected_numbers(report):
    """(element id, text) pairs that the HTML must show."""
    t = report["totals"]
    return [("total-frames", str(t["frames"])),
            ("total-requests", str(t["requests"])),
            ("total-responses", str(t["responses"])),
            ("total-crc", str(t["crc_errors"])),
            ("total-exceptions", str(t["exceptions"])),
            ("total-timeouts", str(t["timeouts"])),
            ("total-damaged-requests", str(t["damaged_requests"])),
            ("total-utilisation", f"{t['bus_utilisation_pct']:.2f}"),
            ("total-slaves", str(t["slaves"])),
            ("turnaround-glitch-line-errors",
             str(report["timing"]["turnaround_glitch"]["line_errors"]))]


def check_numbers(html, report, what):
    for element_id, value in expected_numbers(report):
        if not re.search(rf'id="{element_id}"[^>]*>{re.escape(value)}<', html):
            fail(f"{what}: #{element_id} does not show {value}")
    for addr, slave in report["slaves"].items():
        row = re.search(rf'<tr id="slave-{addr}">(.*?)</tr>', html, re.S)
        if not row:
            fail(f"{what}: no row for slave {addr}")
        cells = re.findall(r"<td[^>]*>(.*?)</td>", row.group(1), re.S)
        if cells[2] != str(slave["requests"]) or cells[3] != str(slave["responses"]):
            fail(f"{what}: slave {addr} row shows {cells[2:4]}, JSON says "
                 f"{slave['requests']}/{slave['responses']}")


RAW_POINT = re.compile(r"(holding|input|coil|discrete) 0x[0-9A-F]{4}")
MAX_POINT_CHARTS = 60  # report_html.cpp: kMaxPointCharts


def check_point_charts(dom, report):
    """Every changing point (up to the chart limit) has its chart; where a slave's model is
    known, its named device points are among them."""
    changing = [p for p in report["points"] if p["changes"] > 0][:MAX_POINT_CHARTS]
    for p in changing:
        label = f'aria-label="slave {p["slave"]} {p["point"]} over time"'
        if html_escape(label) not in dom and label not in dom:
            fail(f"chromium DOM has no chart for slave {p['slave']} point {p['point']!r}")
    known = {int(a) for a, s in report["slaves"].items() if s["device"] is not None}
    named = [p for p in changing if p["slave"] in known and not RAW_POINT.fullmatch(p["point"])]
    if known and not named:
        fail(f"slaves {sorted(known)} have a device model but no named point chart")
    return len(changing), len(named)


def html_escape(text):
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def main():
    global SOURCE_DIR
    args = sys.argv[1:]
    browser = args and args[0] == "--browser"
    if browser:
        args = args[1:]
    rtuscope, capture = args
    rtuscope = os.path.abspath(rtuscope)
    capture = os.path.abspath(capture)
    SOURCE_DIR = os.path.dirname(os.path.dirname(capture))
    options = []
    args_path = re.sub(r"\.[^.]+$", ".args", capture)
    if os.path.exists(args_path):
        options = shlex.split(open(args_path, encoding="utf-8").read())
    work = tempfile.mkdtemp(prefix="rtuscope-report-")
    try:
        report = json.loads(run([rtuscope, "report", capture, "--format", "json"] + options))
        html_path = os.path.join(work, "report.html")
        csv_path = os.path.join(work, "values.csv")
        run([rtuscope, "report", capture, "--format", "html", "-o", html_path,
             "--csv", csv_path] + options)
        html = open(html_path, encoding="utf-8").read()
        if not browser:
            check_json(report)
            text = run([rtuscope, "report", capture] + options)
            t = report["totals"]
            if f"frames            {t['frames']} " not in text:
                fail("text report does not show the frame total")
            if f"bus utilisation   {t['bus_utilisation_pct']:.2f}%" not in text:
                fail("text report does not show the utilisation")
            if "<script" in html.lower() or re.search(r"(src|href)=\"?(https?:)?//", html):
                fail("HTML report is not self-contained")
            check_numbers(html, report, "HTML file")
            rows = open(csv_path, encoding="utf-8").read().splitlines()
            if rows[0] != "time,slave,point,value,unit":
                fail(f"CSV header is {rows[0]!r}")
            for row in rows[1:]:
                if not re.fullmatch(r"-?\d+\.\d{6},\d+,[^,]+,-?[\d.e+-]+,.*", row):
                    fail(f"CSV row {row!r}")
            samples = sum(p["samples"] for p in report["points"])
            if len(rows) - 1 < samples:
                fail(f"CSV has {len(rows) - 1} rows, points hold {samples} samples")
            print(f"ok: {capture}: json, text, html and csv ({len(rows) - 1} values) agree")
            return
        chromium = shutil.which("chromium")
        if chromium is None:
            print("SKIP: chromium is not installed")
            sys.exit(77)
        profile = os.path.join(work, "profile")
        flags = [chromium, "--headless", "--no-sandbox", "--disable-gpu",
                 "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--no-first-run", f"--user-data-dir={profile}"]
        url = "file://" + os.path.abspath(html_path)
        dom = subprocess.run(flags + ["--dump-dom", url], capture_output=True, text=True,
                             timeout=240, check=False)
        if dom.returncode != 0 or "</html>" not in dom.stdout:
            fail(f"chromium could not load the report: {dom.stderr[-2000:]}")
        check_numbers(dom.stdout, report, "chromium DOM")
        if dom.stdout.count("<svg") < 2:
            fail("chromium DOM shows fewer than two charts")
        charts, named = check_point_charts(dom.stdout, report)
        png = os.path.join(work, "report.png")
        shot = subprocess.run(flags + ["--hide-scrollbars", "--window-size=1280,2000",
                                       f"--screenshot={png}", url],
                              capture_output=True, text=True, timeout=240, check=False)
        if shot.returncode != 0 or not os.path.exists(png) or os.path.getsize(png) < 20000:
            fail(f"chromium screenshot missing or empty: {shot.stderr[-2000:]}")
        print(f"ok: chromium renders {capture} with the JSON report's numbers and {charts} "
              f"point charts ({named} named device points)")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
