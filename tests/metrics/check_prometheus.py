#!/usr/bin/env python3
"""The real Prometheus scrapes `rtuscope demo --metrics` (FORMATS §11.3, §11.4).

rtuscope serves on a port the system picks (it prints the URL); Prometheus runs on another
free loopback port with its own storage and a 1 s scrape interval. Once the demo's traffic
is over and the numbers have settled, the test waits until Prometheus holds the final
scrape, queries its HTTP API, stops rtuscope (which writes its report), and checks that the
counters and histogram counts Prometheus stored equal the report's numbers for the run.
The bus name carries a quote and a backslash: it must come back from Prometheus intact.

With --dashboard and --rules it also checks that every metric the Grafana dashboard and the
alert rules use is in rtuscope's exposition, and that every dashboard query is PromQL this
Prometheus accepts (template variables replaced).
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
import urllib.error
import urllib.parse
import urllib.request

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail  # noqa: E402  (after the path line)

BUS = 'cabinet "4"\\west'


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def http_get(url, timeout=5):
    try:
        with urllib.request.urlopen(url, timeout=timeout) as r:
            return r.status, r.headers.get("Content-Type", ""), r.read().decode()
    except urllib.error.HTTPError as e:
        return e.code, e.headers.get("Content-Type", ""), e.read().decode()


def wait_for(what, predicate, deadline_s, step=0.2):
    end = time.monotonic() + deadline_s
    while time.monotonic() < end:
        value = predicate()
        if value:
            return value
        time.sleep(step)
    fail(f"timed out after {deadline_s} s waiting for {what}")


class Prometheus:
    def __init__(self, binary, work):
        self.url = f"http://127.0.0.1:{free_port()}"
        self.binary = binary
        self.work = work
        self.proc = None

    def start(self, target):
        config = os.path.join(self.work, "prometheus.yml")
        with open(config, "w") as f:
            f.write("global:\n  scrape_interval: 1s\n  evaluation_interval: 1s\n"
                    "scrape_configs:\n  - job_name: rtuscope\n    static_configs:\n"
                    f"      - targets: ['{target}']\n")
        self.log = open(os.path.join(self.work, "prometheus.log"), "w")
        self.proc = subprocess.Popen(
            [self.binary, f"--config.file={config}",
             f"--storage.tsdb.path={os.path.join(self.work, 'data')}",
             f"--web.listen-address={self.url[len('http://'):]}"],
            stdout=self.log, stderr=subprocess.STDOUT)

        def ready():
            try:
                return http_get(self.url + "/-/ready")[0] == 200
            except OSError:
                return self.proc.poll() is not None and fail("prometheus exited: see its log")
        wait_for("prometheus to be ready", ready, 20)

    def query(self, promql):
        url = self.url + "/api/v1/query?" + urllib.parse.urlencode({"query": promql})
        status, _, body = http_get(url)
        answer = json.loads(body)
        if status != 200 or answer.get("status") != "success":
            fail(f"query {promql}: {body}")
        return answer["data"]["result"]

    def value(self, promql):
        result = self.query(promql)
        return float(result[0]["value"][1]) if len(result) == 1 else None

    def by(self, promql, label):
        return {r["metric"][label]: float(r["value"][1]) for r in self.query(promql)}

    def stop(self):
        if self.proc and self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        if self.proc:
            self.log.close()


def scrape_value(text, name):
    """The sum of a family's samples in exposition text (to see when numbers settle)."""
    return sum(float(m.group(1)) for m in re.finditer(rf"^{name}{{[^}}]*}} (\S+)$", text, re.M))


def metric_names(promql):
    return set(re.findall(r"\brtuscope_[a-z0-9_]+", promql))


def families(exposition):
    return dict(re.findall(r"^# TYPE (\S+) (\S+)$", exposition, re.M))


def family_of(name, known):
    for suffix in ("_bucket", "_sum", "_count"):
        base = name[:-len(suffix)]
        if name.endswith(suffix) and known.get(base) == "histogram":
            return base
    return name


def dashboard_queries(node):
    """Every PromQL of a Grafana dashboard: panel targets and template variable queries."""
    if isinstance(node, dict):
        for key, value in node.items():
            if key in ("expr", "definition") and isinstance(value, str):
                yield value
            else:
                yield from dashboard_queries(value)
    elif isinstance(node, list):
        for item in node:
            yield from dashboard_queries(item)


def check_names(what, queries, known):
    used = set()
    for q in queries:
        used |= {family_of(n, known) for n in metric_names(q)}
    missing = sorted(used - set(known))
    print(f"{what}: uses {len(used)} metrics, {len(missing)} missing from the exposition")
    if not used or missing:
        fail(f"{what} uses metrics rtuscope does not serve: {missing}")


def check_dashboard_and_rules(args, exposition, prometheus):
    known = families(exposition)
    with open(args.dashboard) as f:
        dashboard = json.load(f)
    queries = list(dashboard_queries(dashboard))
    check_names("dashboard", queries, known)
    with open(args.rules) as f:
        rules = [m.group(1) for m in re.finditer(r"^\s+expr: (?:\|\n)?((?:.|\n)*?)(?=^\s+for:)",
                                                    f.read(), re.M)]
    check_names("alert rules", rules, known)
    answered = 0
    for q in queries:
        if q.startswith("label_values("):  # Grafana's own function, not PromQL
            q = q[len("label_values("):q.rindex(",")]
        q = q.replace("$__rate_interval", "1m").replace("$bus", ".*").replace("$slave", ".*")
        answered += bool(prometheus.query(q))  # fails on a query Prometheus rejects
    print(f"dashboard: {len(queries)} queries valid, {answered} with data")
    if answered < len(queries) // 2:
        fail("most dashboard queries return nothing on the demo's traffic")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--prometheus", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--dashboard")
    ap.add_argument("--rules")
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    work = tempfile.mkdtemp(dir=args.work)
    prometheus = Prometheus(args.prometheus, work)
    demo = None
    started = time.monotonic()
    try:
        report_path = os.path.join(work, "report.json")
        err_path = os.path.join(work, "rtuscope.err")
        with open(err_path, "w") as err:
            demo = subprocess.Popen(
                [args.rtuscope, "demo", "--metrics", "127.0.0.1:0", "--bus-name", BUS,
                 "--report", report_path, "--format", "jsonl"],
                stdout=subprocess.DEVNULL, stderr=err)

        def stderr_text():
            with open(err_path) as f:
                return f.read()

        def served_url():
            if demo.poll() is not None:
                fail(f"rtuscope exited {demo.returncode}: {stderr_text()}")
            m = re.search(r"serving metrics on (http://\S+)", stderr_text())
            return m.group(1) if m else None
        metrics_url = wait_for("rtuscope to serve metrics", served_url, 20)
        status, content_type, text = http_get(metrics_url)
        if status != 200 or "version=0.0.4" not in content_type:
            fail(f"GET {metrics_url}: {status} {content_type}")
        if http_get(metrics_url.replace("/metrics", "/"))[0] != 404:
            fail("/ should answer 404: only /metrics is served")
        prometheus.start(urllib.parse.urlparse(metrics_url).netloc)

        wait_for("the demo's traffic to end", lambda: "traffic over" in stderr_text(), 60)

        # Settled: the last request's response timeout has run out; two scrapes agree.
        def settled():
            first = http_get(metrics_url)[2]
            time.sleep(1.5)
            second = http_get(metrics_url)[2]
            keep = lambda t: [l for l in t.splitlines() if "seconds_since" not in l
                              and "utilisation" not in l]
            return second if keep(first) == keep(second) else None
        final = wait_for("the counters to settle", settled, 20, step=0)
        frames = scrape_value(final, "rtuscope_frames_total")
        if frames <= 0:
            fail("no frames counted")

        selector = '{job="rtuscope"}'
        wait_for("prometheus to scrape the final numbers",
                 lambda: prometheus.value(f"sum(rtuscope_frames_total{selector})") == frames
                 and prometheus.value("max(up)") == 1, 30, step=0.5)

        got = {
            "frames": prometheus.value("sum(rtuscope_frames_total)"),
            "bytes": prometheus.value("sum(rtuscope_bytes_total)"),
            "noise_bytes": prometheus.value("sum(rtuscope_noise_bytes_total)"),
            "requests": prometheus.by("sum by (slave) (rtuscope_requests_total)", "slave"),
            "responses": prometheus.by("sum by (slave) (rtuscope_responses_total)", "slave"),
            "exceptions": prometheus.by("sum by (slave) (rtuscope_exceptions_total)", "slave"),
            "timeouts": prometheus.by("sum by (slave) (rtuscope_timeouts_total)", "slave"),
            "crc_errors": prometheus.by("sum by (slave) (rtuscope_crc_errors_total)", "slave"),
            "latency_count": prometheus.by(
                "sum by (slave) (rtuscope_response_latency_seconds_count)", "slave"),
            "latency_unseen": prometheus.by(
                "sum by (slave) (rtuscope_response_latency_unseen_total)", "slave"),
            "latency_inf": prometheus.by(
                'sum by (slave) (rtuscope_response_latency_seconds_bucket{le="+Inf"})', "slave"),
            "p50": prometheus.by(
                "histogram_quantile(0.5, sum by (slave, le) "
                "(rtuscope_response_latency_seconds_bucket))", "slave"),
            "buses": {r["metric"]["bus"] for r in prometheus.query("rtuscope_frames_total")},
            "models": prometheus.by("sum by (model) (rtuscope_timeouts_total)", "model"),
        }

        if args.dashboard:
            check_dashboard_and_rules(args, final, prometheus)

        demo.send_signal(signal.SIGTERM)
        if demo.wait(timeout=30) != 0:
            fail(f"rtuscope exited {demo.returncode}: {stderr_text()}")
        demo = None
        with open(report_path) as f:
            report = json.load(f)
        totals, slaves = report["totals"], report["slaves"]

        def expect(what, have, want):
            print(f"{what}: prometheus {have}, report {want}")
            if have != want:
                fail(f"{what}: prometheus has {have}, the report {want}")

        expect("frames", got["frames"], totals["frames"])
        expect("bytes", got["bytes"], totals["bytes"])
        expect("noise bytes", got["noise_bytes"], totals["noise_bytes"])
        for key, report_key in (("requests", "requests"), ("responses", "responses"),
                                ("exceptions", "exceptions"), ("timeouts", "timeouts"),
                                ("crc_errors", "crc_errors"), ("latency_count", "latency_samples"),
                                ("latency_inf", "latency_samples"),
                                ("latency_unseen", "latency_unseen")):
            want = {s: float(v[report_key]) for s, v in slaves.items()
                    if v[report_key] or key in ("requests", "timeouts", "crc_errors")}
            have = {s: v for s, v in got[key].items() if v or s in want}
            expect(f"{key} by slave", have, want)
        expect("total timeouts", sum(got["timeouts"].values()), totals["timeouts"])
        expect("total exceptions", sum(got["exceptions"].values()), totals["exceptions"])
        expect("bus label", got["buses"], {BUS})
        expect("models", set(got["models"]), {v["device"] for v in slaves.values()})
        for slave, p50 in got["p50"].items():
            lat = slaves[slave]["latency_ms"]
            print(f"slave {slave}: histogram p50 {p50 * 1e3:.2f} ms, report p50 {lat['p50']} ms")
            # The histogram interpolates inside its bucket: the median lies in the same
            # bucket as the report's, within the buckets' bounds 5-10-20 ms around it.
            if not lat["min"] / 1e3 * 0.5 <= p50 <= lat["max"] / 1e3 * 2:
                fail(f"slave {slave}: p50 {p50} s is outside the latencies seen {lat}")
        print(f"passed in {time.monotonic() - started:.1f} s")
    finally:
        if demo is not None and demo.poll() is None:
            demo.kill()
            demo.wait()
        prometheus.stop()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
