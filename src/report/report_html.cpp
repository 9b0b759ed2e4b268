// The HTML report: one self-contained page (inline CSS and SVG, no script, nothing fetched)
// that a commissioning engineer can hand over. Numbers come from the same TrafficStats as
// the JSON report, formatted the same way where both show them.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/function_codes.hpp"
#include "core/time_format.hpp"
#include "report/report_writers.hpp"
#include "report/svg_chart.hpp"
#include "report/timing_note.hpp"

namespace rtu {

namespace {

using Out = fmt::memory_buffer;
using svg::append_escaped;
using svg::escaped;

constexpr std::size_t kMaxPointCharts = 60;

constexpr std::string_view kStyle = R"css(
:root{--ink:#1d2733;--muted:#5b6b7c;--line:#d9e0e7;--bg:#f4f6f8;--card:#fff;--accent:#1f6fb2;
--err:#c0392b;--warn:#d68910;--info:#2e86c1;--ok:#1e8449}
*{box-sizing:border-box}
body{margin:0;background:var(--bg);color:var(--ink);font:14px/1.45 "DejaVu Sans","Segoe UI",Helvetica,Arial,sans-serif}
header{background:#17324d;color:#fff;padding:22px 36px 18px}
header h1{margin:0 0 4px;font-size:22px;font-weight:600;letter-spacing:.2px}
header .meta{color:#c8d6e5;font-size:13px}
main{max-width:1180px;margin:0 auto;padding:20px 28px 48px}
@media (max-width:600px){main{padding:12px 8px 32px}section{padding:12px 10px}header{padding:16px 14px}table.kv{min-width:0}}
section{background:var(--card);border:1px solid var(--line);border-radius:6px;margin:18px 0;padding:16px 20px}
h2{font-size:16px;margin:0 0 12px;color:#17324d;font-weight:600}
h3{font-size:13px;margin:0 0 6px;color:var(--muted);font-weight:600}
.cards{display:grid;grid-template-columns:repeat(auto-fill,minmax(150px,1fr));gap:10px;margin-bottom:14px}
.card{border:1px solid var(--line);border-radius:5px;padding:10px 12px;background:#fbfcfd}
.card .v{font-size:22px;font-weight:600}
.card .k{color:var(--muted);font-size:12px}
.card.bad .v{color:var(--err)}
table{border-collapse:collapse;width:100%;font-size:13px}
table.kv{width:auto;min-width:420px}
table.kv th{background:none;text-align:left;font-weight:normal;color:var(--muted);padding-right:40px}
td.wrap{white-space:normal;text-align:left;font-size:12px;min-width:130px}
.scroll{overflow-x:auto;max-width:100%}
th,td{padding:5px 8px;border-bottom:1px solid var(--line);text-align:right;white-space:nowrap}
thead th{white-space:normal;vertical-align:bottom}
svg.timeline,svg.util{min-width:720px}
th{background:#eef2f6;color:#33475b;font-weight:600}
td.l,th.l{text-align:left}
tr:hover td{background:#f7fafc}
.num0{color:#9aa8b6}
.finding{border-left:5px solid var(--info);padding:8px 12px;margin:8px 0;background:#fbfcfd;border-radius:0 5px 5px 0}
.finding.error{border-color:var(--err)}.finding.warning{border-color:var(--warn)}
.finding .head{font-weight:600}
.finding .sev{display:inline-block;min-width:64px;font-size:11px;text-transform:uppercase;letter-spacing:.5px;color:#fff;background:var(--info);border-radius:3px;padding:1px 6px;margin-right:8px;text-align:center}
.finding.error .sev{background:var(--err)}.finding.warning .sev{background:var(--warn)}
.finding .key{font-family:"DejaVu Sans Mono",monospace;font-size:12px;color:var(--muted);margin-left:6px}
.finding .cause{color:#33475b;margin-top:3px}
.finding .ev{margin-top:4px}
.chip{display:inline-block;font-size:11px;background:#eef2f6;border-radius:10px;padding:1px 8px;margin:2px 4px 0 0;color:#33475b}
.none{color:var(--ok);font-weight:600}
.sub{font-size:11px;color:var(--muted)}
.note{color:var(--muted);font-size:12px;margin-top:6px}
svg{display:block;max-width:100%;height:auto}
svg text{font-size:10px;fill:#5b6b7c;font-family:"DejaVu Sans",Helvetica,Arial,sans-serif}
svg .ylab{text-anchor:end}svg .xlab{text-anchor:middle}
svg .grid{stroke:#e6ebf0;stroke-width:1}svg .axis{stroke:#8a99a8;stroke-width:1}svg .tick{stroke:#8a99a8}
svg .req{fill:#1f6fb2}svg .rsp{fill:#7fb3e0}
svg .util{fill:#1f6fb2;fill-opacity:.18;stroke:#1f6fb2;stroke-width:1.2}
svg .bar{fill:#1f6fb2}svg .pct{stroke-width:1;stroke-dasharray:3 2}
svg .band{fill:#1f6fb2;fill-opacity:.15}svg .val{fill:none;stroke:#1f6fb2;stroke-width:1.3}
svg .lane{fill:#f4f6f8}svg .lanelab{text-anchor:end}
.grid2{display:grid;grid-template-columns:repeat(auto-fill,minmax(min(340px,100%),1fr));gap:14px}
.grid3{display:grid;grid-template-columns:repeat(auto-fill,minmax(min(270px,100%),1fr));gap:12px}
.small{border:1px solid var(--line);border-radius:5px;padding:8px 10px;background:#fbfcfd}
.legend span{display:inline-block;margin-right:14px;font-size:12px;color:var(--muted)}
.legend i{display:inline-block;width:10px;height:10px;margin-right:5px;vertical-align:-1px;border-radius:2px}
footer{color:var(--muted);font-size:12px;text-align:center;margin-top:24px}
)css";

template <typename... Args>
void put(Out& o, fmt::format_string<Args...> f, Args&&... args) {
  fmt::format_to(std::back_inserter(o), f, std::forward<Args>(args)...);
}

void text(Out& o, std::string_view s) {
  append_escaped(o, s);
}

std::string ms_text(Nanos t) {
  return fmt::format("{:.1f}", to_millis(t));
}

std::string count_cell(std::uint64_t n, bool flag_nonzero = false) {
  if (n == 0) return "<td class=\"num0\">0</td>";
  if (flag_nonzero) return fmt::format("<td style=\"color:var(--err);font-weight:600\">{}</td>", n);
  return fmt::format("<td>{}</td>", n);
}

double span_seconds(const TrafficStats& stats) {
  return std::max(to_seconds(stats.totals().duration()), 1e-3);
}

std::size_t used_buckets(const TrafficStats& stats) {
  const auto& tl = stats.timeline();
  if (stats.totals().first_t == kUnknownTime) return 0;
  std::size_t n = 0;
  while (n < tl.size() && tl.bucket_start(n) < stats.totals().last_t) ++n;
  return std::max<std::size_t>(n, 1);
}

void header(Out& o, const TrafficStats& stats) {
  const CaptureInfo& info = stats.capture();
  const Totals& t = stats.totals();
  put(o, "<header><h1>Modbus RTU bus report</h1><div class=\"meta\">");
  text(o, info.source);
  put(o, " &middot; {} &middot; ", escaped(info.line.describe()));
  if (t.first_t != kUnknownTime && t.first_t >= kWallClockFrom) {
    Out b;
    append_utc_date(b, t.first_t);
    b.push_back(' ');
    append_utc_time_of_day(b, t.first_t, 0);
    put(o, "from {} UTC, ", fmt::to_string(b));
  } else if (t.first_t != kUnknownTime) {
    Out b;
    append_seconds(b, t.first_t, 3);
    put(o, "from t = {} s, ", escaped(fmt::to_string(b)));
  }
  put(o, "{:.3f} s of traffic</div></header>", to_seconds(t.duration()));
}

void card(Out& o, std::string_view id, std::string_view label, const std::string& value,
          bool bad = false) {
  put(o, "<div class=\"card{}\"><div class=\"v\" id=\"{}\">{}</div><div class=\"k\">{}</div></div>",
      bad ? " bad" : "", id, value, label);
}

void summary(Out& o, const TrafficStats& stats) {
  const Totals& t = stats.totals();
  const CaptureInfo& info = stats.capture();
  std::size_t slaves = 0;
  for (unsigned a = 1; a < 256; ++a) {
    if (stats.slave(static_cast<std::uint8_t>(a)) != nullptr) ++slaves;
  }
  put(o, "<section id=\"summary\"><h2>Summary</h2>");
  // Doubts about the capture itself come first: they may change how everything below reads.
  for (const std::string& w : info.warnings) {
    put(o, "<div class=\"finding warning capture-warning\"><span class=\"sev\">warning</span>");
    text(o, w);
    put(o, "</div>");
  }
  put(o, "<div class=\"cards\">");
  card(o, "total-duration", "duration (s)", fmt::format("{:.3f}", to_seconds(t.duration())));
  card(o, "total-frames", "frames", fmt::format("{}", t.frames));
  card(o, "total-slaves", "slaves", fmt::format("{}", slaves));
  card(o, "total-utilisation", "bus utilisation (%)",
       fmt::format("{:.2f}", t.utilisation() * 100.0));
  card(o, "total-crc", "CRC errors", fmt::format("{}", t.issues[IssueId::kCrc]),
       t.issues[IssueId::kCrc] > 0);
  card(o, "total-exceptions", "exceptions", fmt::format("{}", t.exceptions), t.exceptions > 0);
  card(o, "total-timeouts", "timeouts", fmt::format("{}", t.timeouts), t.timeouts > 0);
  card(o, "total-line-errors", "line errors", fmt::format("{}", t.line_error_records),
       t.line_error_records > 0);
  put(o, "</div><div class=\"scroll\"><table class=\"kv\"><tbody>");
  auto row = [&](std::string_view id, std::string_view k, const std::string& v) {
    put(o, "<tr><th class=\"l\">{}</th><td id=\"{}\">{}</td></tr>", k, id, v);
  };
  row("total-requests", "requests", fmt::format("{}", t.requests));
  row("total-responses", "responses", fmt::format("{}", t.responses));
  row("total-broadcasts", "broadcasts", fmt::format("{}", t.broadcasts));
  row("total-bytes", "bytes on the line", fmt::format("{}", t.bytes));
  row("total-noise", "noise bytes (in records)",
      fmt::format("{} ({})", t.noise_bytes, t.noise_records));
  row("total-damaged-requests", "damaged requests, unanswered (not timeouts)",
      fmt::format("{}", t.damaged_requests));
  row("total-late", "late responses", fmt::format("{}", t.issues[IssueId::kLate]));
  row("total-unsolicited", "unsolicited / wrong slave",
      fmt::format("{} / {}", t.issues[IssueId::kUnsolicited], t.issues[IssueId::kWrongSlave]));
  row("total-line-detail", "line errors: parity / framing / break / overrun",
      fmt::format("{} / {} / {} / {}", t.parity_errors, t.framing_errors, t.breaks, t.overruns));
  row("total-resolution", "timing resolution (ms)", resolution_text(info));
  row("total-timeout", "response timeout assumed (ms)",
      fmt::format("{:.0f}", to_millis(info.response_timeout)));
  put(o, "</tbody></table></div><div class=\"note\">");
  text(o, timing_note(info));
  put(o, "</div></section>");
}

void findings_section(Out& o, const std::vector<Finding>& findings, bool any_traffic) {
  put(o, "<section id=\"findings\"><h2>Findings</h2>");
  if (findings.empty()) {
    if (any_traffic) {
      put(o, "<p class=\"none\">Nothing in this capture points to a problem.</p>");
    } else {
      put(o, "<p class=\"none\">None: the capture holds no traffic to judge.</p>");
    }
  }
  for (const Finding& f : findings) {
    const std::string_view sev = severity_name(f.severity);
    put(o,
        "<div class=\"finding {}\" data-key=\"{}\"><div class=\"head\"><span "
        "class=\"sev\">{}</span>",
        sev, escaped(f.key), sev);
    text(o, f.summary);
    put(o,
        "<span class=\"key\">{}</span></div><div class=\"cause\">Likely cause: ", escaped(f.key));
    text(o, f.cause);
    put(o, "</div><div class=\"ev\">");
    for (const Evidence& e : f.evidence) {
      const bool whole = e.value == std::round(e.value);
      put(o, "<span class=\"chip\">{} = {}{}</span>", escaped(e.name),
          whole ? fmt::format("{:.0f}", e.value) : fmt::format("{:.3f}", e.value),
          escaped(e.unit.empty() ? "" : " " + e.unit));
    }
    put(o, "</div></div>");
  }
  put(o, "</section>");
}

// Requests and responses per bucket as stacked bars, errors in lanes below.
void timeline_chart(Out& o, const TrafficStats& stats) {
  const auto& tl = stats.timeline();
  const std::size_t n = used_buckets(stats);
  put(o, "<section id=\"timeline\"><h2>Traffic and errors over time</h2>");
  if (n == 0) {
    put(o, "<p class=\"note\">No traffic.</p></section>");
    return;
  }
  const double w = to_seconds(tl.width());
  std::uint64_t peak = 1;
  for (std::size_t i = 0; i < n; ++i) peak = std::max(peak, tl[i].frames);
  struct Lane {
    std::string_view name;
    std::string_view colour;
    std::uint64_t (*count)(const TrafficBucket&);
  };
  const Lane lanes[] = {
      {"CRC errors", "#c0392b", [](const TrafficBucket& b) { return b.issues[IssueId::kCrc]; }},
      {"timeouts", "#d68910", [](const TrafficBucket& b) { return b.timeouts; }},
      {"exceptions", "#8e44ad", [](const TrafficBucket& b) { return b.exceptions; }},
      {"line errors", "#e74c3c", [](const TrafficBucket& b) { return b.line_errors; }},
      {"noise bytes", "#7f8c8d", [](const TrafficBucket& b) { return b.noise_bytes; }}};
  constexpr double kLane = 14;
  svg::Frame f;
  f.width = 1100;
  f.height = 190 + 5 * kLane + 10;
  f.left = 84;
  f.bottom = 28 + 5 * kLane + 10;
  f.x_lo = 0;
  f.x_hi = w * static_cast<double>(n);
  f.y_lo = 0;
  f.y_hi = std::max(4.0, static_cast<double>(peak));
  put(o, "<div class=\"scroll\">");
  svg::open(o, f, "frames per time bucket, with error lanes", "timeline");
  f.y_hi = std::max(f.y_hi, svg::nice_ticks(0, f.y_hi, 4).back());
  // Lanes sit below the axis labels.
  svg::y_axis(o, f, svg::nice_ticks(0, f.y_hi, 4), "");
  const svg::TimeAxis xt = svg::time_axis(stats.totals().first_t, f.x_hi, 8);
  svg::x_axis(o, f, xt.ticks, xt.labels);
  const double bw = f.px(w) - f.px(0);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = f.px(w * static_cast<double>(i));
    const auto req = static_cast<double>(tl[i].requests);
    const auto other = static_cast<double>(tl[i].frames - tl[i].requests);
    if (req > 0) {
      put(o, "<rect class=\"req\" x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\"/>",
          x, f.py(req), std::max(bw - 0.5, 0.6), f.py(0) - f.py(req));
    }
    if (other > 0) {
      put(o, "<rect class=\"rsp\" x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\"/>",
          x, f.py(req + other), std::max(bw - 0.5, 0.6), f.py(req) - f.py(req + other));
    }
  }
  const double lane_top = f.height - 5 * kLane - 8;
  for (std::size_t l = 0; l < 5; ++l) {
    const double y = lane_top + static_cast<double>(l) * kLane;
    put(o,
        "<rect class=\"lane\" x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\"/>"
        "<text class=\"lanelab\" x=\"{:.1f}\" y=\"{:.1f}\">{}</text>",
        f.left, y, f.plot_width(), kLane - 3, f.left - 4, y + 9, lanes[l].name);
    std::uint64_t lane_peak = 1;
    for (std::size_t i = 0; i < n; ++i) lane_peak = std::max(lane_peak, lanes[l].count(tl[i]));
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t v = lanes[l].count(tl[i]);
      if (v == 0) continue;
      const double op = 0.35 + 0.65 * static_cast<double>(v) / static_cast<double>(lane_peak);
      put(o,
          "<rect x=\"{:.2f}\" y=\"{:.1f}\" width=\"{:.2f}\" height=\"{:.1f}\" fill=\"{}\" "
          "fill-opacity=\"{:.2f}\"><title>{}: {}</title></rect>",
          f.px(w * static_cast<double>(i)), y, std::max(bw, 1.5), kLane - 3, lanes[l].colour, op,
          lanes[l].name, v);
    }
  }
  svg::close(o);
  put(o, "</div>");
  put(o,
      "<div class=\"legend\"><span><i style=\"background:#1f6fb2\"></i>requests</span>"
      "<span><i style=\"background:#7fb3e0\"></i>responses and other frames</span>"
      "<span>bucket {:.3f} s</span><span>{}</span></div></section>",
      w, xt.caption());
}

void utilisation_chart(Out& o, const TrafficStats& stats) {
  const auto& tl = stats.timeline();
  const std::size_t n = used_buckets(stats);
  put(o, "<section id=\"utilisation\"><h2>Bus utilisation over time</h2>");
  if (n == 0) {
    put(o, "<p class=\"note\">No traffic.</p></section>");
    return;
  }
  const double w = to_seconds(tl.width());
  svg::Frame f;
  f.width = 1100;
  f.height = 170;
  f.x_lo = 0;
  f.x_hi = w * static_cast<double>(n);
  f.y_lo = 0;
  f.y_hi = 100;
  put(o, "<div class=\"scroll\">");
  svg::open(o, f, "share of time the line carries bytes, per time bucket", "util");
  svg::y_axis(o, f, {0, 25, 50, 75, 100}, "%");
  const svg::TimeAxis xt = svg::time_axis(stats.totals().first_t, f.x_hi, 8);
  svg::x_axis(o, f, xt.ticks, xt.labels);
  put(o, "<path class=\"util\" d=\"M{:.2f},{:.2f}", f.px(0), f.py(0));
  const double width_ns = static_cast<double>(tl.width());
  for (std::size_t i = 0; i < n; ++i) {
    const double u = std::min(100.0, 100.0 * tl[i].busy_ns / width_ns);
    put(o, " L{:.2f},{:.2f} L{:.2f},{:.2f}", f.px(w * static_cast<double>(i)), f.py(u),
        f.px(w * static_cast<double>(i + 1)), f.py(u));
  }
  put(o, " L{:.2f},{:.2f} Z\"/>", f.px(w * static_cast<double>(n)), f.py(0));
  svg::close(o);
  put(o, "</div>");
  put(o,
      "<div class=\"note\">Busy time = bytes × character time ({:.3f} ms at {}); overall "
      "{:.2f}%. Time axis: {}.</div></section>",
      to_millis(stats.capture().line.char_time()), escaped(stats.capture().line.describe()),
      stats.totals().utilisation() * 100.0, xt.caption());
}

std::string device_cell(const TrafficStats& stats, std::uint8_t address) {
  const std::string_view model = stats.device_model(address);
  if (model.empty()) return "&ndash;";
  if (!stats.device_model_identified(address)) return escaped(model);
  return fmt::format(
      "{}<div class=\"sub\" title=\"recognised from the traffic; name it with --device or "
      "--bus\">identified</div>",
      escaped(model));
}

void slave_table(Out& o, const TrafficStats& stats) {
  put(o,
      "<section id=\"slaves\"><h2>Slaves</h2><div class=\"scroll\"><table><thead><tr><th "
      "class=\"l\">slave</th>"
      "<th class=\"l\">device</th><th>requests</th><th>responses</th><th>exceptions</th>"
      "<th>timeouts</th><th>damaged requests</th><th>CRC errors</th><th>unsolicited</th>"
      "<th>wrong slave</th>"
      "<th>latency min</th><th>p50</th><th>p95</th><th>p99</th><th>max (ms)</th>"
      "<th class=\"l\">functions</th></tr></thead><tbody>");
  for (unsigned a = 1; a < 256; ++a) {
    const SlaveStats* s = stats.slave(static_cast<std::uint8_t>(a));
    if (s == nullptr) continue;
    put(o,
        "<tr id=\"slave-{}\"><td class=\"l\">{}</td><td class=\"l\">{}</td><td "
        "class=\"req\">{}</td>"
        "<td class=\"rsp\">{}</td>{}{}{}{}{}{}",
        a, a, device_cell(stats, static_cast<std::uint8_t>(a)), s->requests, s->responses,
        count_cell(s->exceptions, true), count_cell(s->timeouts, true),
        count_cell(s->damaged_requests, true), count_cell(s->issues[IssueId::kCrc], true),
        count_cell(s->issues[IssueId::kUnsolicited], true),
        count_cell(s->issues[IssueId::kWrongSlave], true));
    // Answers in their request's read show no latency: said, not counted as 0 ms.
    const std::string unseen =
        s->latency_unseen > 0
            ? fmt::format("<br><span class=\"num0\">not seen for {} in their request's read</span>",
                          s->latency_unseen)
            : "";
    if (s->latency.empty()) {
      put(o, "<td colspan=\"5\" class=\"num0\">no timed answers{}</td>", unseen);
    } else {
      put(o, "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}{}</td>", ms_text(s->latency.min()),
          ms_text(s->latency.quantile(0.5)), ms_text(s->latency.quantile(0.95)),
          ms_text(s->latency.quantile(0.99)), ms_text(s->latency.max()), unseen);
    }
    put(o, "<td class=\"wrap\">");
    bool first = true;
    for (const auto& [fc, n] : s->functions) {
      put(o, "{}<span title=\"{}\">{:02d}</span>&times;{}", first ? "" : ", ",
          escaped(function_name(fc)), fc, n);
      first = false;
    }
    put(o, "</td></tr>");
    for (const auto& [code, n] : s->exception_codes) {
      put(o,
          "<tr><td></td><td class=\"l\" colspan=\"15\" style=\"color:var(--muted)\">exception "
          "{:02X} {} &times;{}</td></tr>",
          code, escaped(stats.exception_name(static_cast<std::uint8_t>(a), code)), n);
    }
    const std::string issues = issue_counts_text(s->issues);
    if (!issues.empty()) {
      put(o,
          "<tr><td></td><td class=\"l\" colspan=\"15\" style=\"color:var(--muted)\">issues: "
          "{}</td></tr>",
          escaped(issues));
    }
  }
  put(o, "</tbody></table></div>");
  if (const auto& sample = stats.identification()) {
    std::string note = describe(*sample);
    note[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(note[0])));
    put(o, "<div class=\"note\">{}.</div>", escaped(note));
  }
  put(o, "</section>");
}

void latency_histograms(Out& o, const TrafficStats& stats) {
  put(o, "<section id=\"latency\"><h2>Response latency per slave</h2><div class=\"grid2\">");
  bool any = false;
  for (unsigned a = 1; a < 256; ++a) {
    const SlaveStats* s = stats.slave(static_cast<std::uint8_t>(a));
    if (s == nullptr || s->latency.empty()) continue;
    any = true;
    const LogHistogram& h = s->latency;
    constexpr std::size_t kBins = 30;
    double lo = std::max(0.0, to_millis(h.min()));
    double hi = to_millis(h.max());
    if (hi - lo < 1.0) {
      lo = std::max(0.0, lo - 0.5);
      hi = lo + 1.0;
    }
    const auto ticks = svg::nice_ticks(lo, hi, 5);
    lo = std::min(lo, ticks.front());
    std::array<std::uint64_t, kBins> bins{};
    const double bin_w = (hi - lo) / kBins;
    h.for_each_bucket([&](Nanos b_lo, Nanos b_hi, std::uint64_t count) {
      const double mid = (to_millis(b_lo) + to_millis(b_hi)) / 2.0;
      auto k = static_cast<std::size_t>(std::max(0.0, (mid - lo) / bin_w));
      bins[std::min(k, kBins - 1)] += count;
    });
    std::uint64_t peak = 1;
    for (const auto c : bins) peak = std::max(peak, c);
    svg::Frame f;
    f.width = 360;
    f.height = 150;
    f.left = 40;
    f.x_lo = lo;
    f.x_hi = hi;
    f.y_hi = std::max(4.0, static_cast<double>(peak));  // whole-number count ticks
    const std::string_view model = stats.device_model(static_cast<std::uint8_t>(a));
    put(o, "<div class=\"small\"><h3>slave {}{}{} &middot; {} answers</h3>", a,
        model.empty() ? "" : " &middot; ", escaped(model), h.count());
    svg::open(o, f, fmt::format("latency histogram of slave {}", a), "hist");
    const auto yt = svg::nice_ticks(0, f.y_hi, 3);
    svg::axes(
        o, f, ticks, yt, [](double x) { return svg::tick_label(x); }, "");
    for (std::size_t k = 0; k < kBins; ++k) {
      if (bins[k] == 0) continue;
      const double x0 = f.px(lo + bin_w * static_cast<double>(k));
      const double x1 = f.px(lo + bin_w * static_cast<double>(k + 1));
      put(o,
          "<rect class=\"bar\" x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\">"
          "<title>{:.1f}-{:.1f} ms: {}</title></rect>",
          x0, f.py(static_cast<double>(bins[k])), std::max(x1 - x0 - 0.6, 0.8),
          f.py(0) - f.py(static_cast<double>(bins[k])), lo + bin_w * static_cast<double>(k),
          lo + bin_w * static_cast<double>(k + 1), bins[k]);
    }
    const std::pair<double, std::string_view> marks[] = {
        {0.5, "#1e8449"}, {0.95, "#d68910"}, {0.99, "#c0392b"}};
    for (const auto& [p, colour] : marks) {
      const double x = f.px(to_millis(h.quantile(p)));
      put(o,
          "<line class=\"pct\" x1=\"{:.2f}\" y1=\"{:.1f}\" x2=\"{:.2f}\" y2=\"{:.1f}\" "
          "stroke=\"{}\"/>",
          x, f.top, x, f.height - f.bottom, colour);
    }
    svg::close(o);
    put(o,
        "<div class=\"note\">ms; <span style=\"color:#1e8449\">p50 {}</span> &middot; "
        "<span style=\"color:#d68910\">p95 {}</span> &middot; <span style=\"color:#c0392b\">"
        "p99 {}</span> &middot; max {}</div></div>",
        ms_text(h.quantile(0.5)), ms_text(h.quantile(0.95)), ms_text(h.quantile(0.99)),
        ms_text(h.max()));
  }
  if (!any) put(o, "<p class=\"note\">No response was timed.</p>");
  put(o, "</div></section>");
}

void poll_table(Out& o, const TrafficStats& stats) {
  put(o,
      "<section id=\"polls\"><h2>Poll periods per request kind</h2><div "
      "class=\"scroll\"><table><thead><tr>"
      "<th class=\"l\">slave</th><th class=\"l\">function</th><th>address</th><th>quantity</th>"
      "<th>requests</th><th>responses</th><th>exceptions</th><th>timeouts</th>"
      "<th>period p50</th><th>min</th><th>p95</th><th>max (ms)</th></tr></thead><tbody>");
  for (const auto& [kind, k] : stats.request_kinds()) {
    put(o, "<tr><td class=\"l\">{}</td><td class=\"l\">{:02d} {}</td>", kind.slave, kind.function,
        escaped(function_short_name(kind.function)));
    if (kind.has_range) {
      put(o, "<td>0x{:04X}</td><td>{}</td>", kind.addr, kind.qty);
    } else {
      put(o, "<td>&ndash;</td><td>&ndash;</td>");
    }
    put(o, "<td>{}</td><td>{}</td>{}{}", k.count, k.responses, count_cell(k.exceptions, true),
        count_cell(k.timeouts, true));
    if (k.period.empty()) {
      put(o, "<td colspan=\"4\" class=\"num0\">once</td>");
    } else {
      put(o, "<td><b>{}</b></td><td>{}</td><td>{}</td><td>{}</td>", ms_text(k.period.quantile(0.5)),
          ms_text(k.period.min()), ms_text(k.period.quantile(0.95)), ms_text(k.period.max()));
    }
    put(o, "</tr>");
  }
  put(o, "</tbody></table></div>");
  if (stats.request_kinds_overflow() > 0) {
    put(o, "<div class=\"note\">{} requests of further kinds are counted but not tabled.</div>",
        stats.request_kinds_overflow());
  }
  put(o, "</section>");
}

void timing_section(Out& o, const TrafficStats& stats) {
  const CaptureInfo& info = stats.capture();
  const Totals& t = stats.totals();
  auto pct_row = [&](std::string_view name, const LogHistogram& h) {
    put(o, "<tr><th class=\"l\">{}</th>", name);
    if (h.empty()) {
      put(o, "<td colspan=\"5\" class=\"num0\">not observed</td></tr>");
      return;
    }
    put(o, "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>", ms_text(h.min()),
        ms_text(h.quantile(0.5)), ms_text(h.quantile(0.95)), ms_text(h.quantile(0.99)),
        ms_text(h.max()));
  };
  put(o,
      "<section id=\"timing\"><h2>Timing diagnostics</h2><div "
      "class=\"scroll\"><table><thead><tr><th class=\"l\">"
      "turnaround</th><th>min</th><th>p50</th><th>p95</th><th>p99</th><th>max (ms)</th></tr>"
      "</thead><tbody>");
  pct_row("slave: request end &rarr; response start", stats.all_latencies());
  pct_row("master: response end &rarr; next request", stats.master_turnaround());
  put(o, "</tbody></table></div><div class=\"scroll\"><table style=\"margin-top:10px\"><tbody>");
  put(o, "<tr><th class=\"l\">t1.5 = {:.3f} ms, t3.5 = {:.3f} ms</th><td></td></tr>",
      to_millis(info.line.t1_5()), to_millis(info.line.t3_5()));
  put(o, "<tr><th class=\"l\">pauses &gt; t1.5 inside frames</th><td>{}</td></tr>",
      stats.t15_observable() ? fmt::format("{}", t.issues[IssueId::kT15]) : "not observable");
  put(o, "<tr><th class=\"l\">frames &lt; t3.5 after the previous one</th><td>{}</td></tr>",
      stats.t35_observable() ? fmt::format("{}", t.issues[IssueId::kT35]) : "not observable");
  put(o,
      "<tr><th class=\"l\">lone bytes right after a frame (driver glitches at turnaround): "
      "after the master's frames / after slaves' frames</th><td id=\"turnaround-glitch\">{} / "
      "{}</td></tr>",
      stats.master_turnaround_glitches(),
      t.turnaround_glitch_records - stats.master_turnaround_glitches());
  // A framing error or break on them is the undriven bus (missing bias), not a device.
  put(o,
      "<tr><th class=\"l\">of those, with a framing error or break (the bus floating at "
      "turnaround)</th><td id=\"turnaround-glitch-line-errors\">{}</td></tr>",
      t.turnaround_glitch_line_errors);
  for (unsigned a = 1; a < 256; ++a) {
    const SlaveStats* s = stats.slave(static_cast<std::uint8_t>(a));
    if (s == nullptr) continue;
    if (s->t15_responses + s->t35_responses + s->t15_requests + s->t35_requests == 0) continue;
    put(o,
        "<tr><th class=\"l\">slave {}: t1.5 pauses in requests / responses, t3.5 early "
        "requests / responses</th><td>{} / {}, {} / {}</td></tr>",
        a, s->t15_requests, s->t15_responses, s->t35_requests, s->t35_responses);
  }
  put(o, "</tbody></table></div><div class=\"note\">");
  text(o, timing_note(info));
  put(o, "</div></section>");
}

void points_section(Out& o, const TrafficStats& stats) {
  put(o, "<section id=\"points\"><h2>Register values over time</h2>");
  std::size_t changing = 0;
  std::size_t constant = 0;
  for (const auto& [key, p] : stats.points()) (p.changes > 0 ? changing : constant)++;
  if (stats.points().empty()) {
    put(o, "<p class=\"note\">No register values were read in this capture.</p></section>");
    return;
  }
  const double span = span_seconds(stats);
  const Nanos t0 = stats.totals().first_t;
  const svg::TimeAxis xt = svg::time_axis(t0, span, 4);
  put(o,
      "<div class=\"note\" style=\"margin:0 0 8px\">{} points change and are drawn below "
      "(time axis: {}); {} stay constant (see the table).</div><div class=\"grid3\">",
      changing, xt.caption(), constant);
  std::size_t drawn = 0;
  for (const auto& [key, p] : stats.points()) {
    if (p.changes == 0) continue;
    if (drawn++ >= kMaxPointCharts) break;
    svg::Frame f;
    f.width = 300;
    f.height = 110;
    f.left = 46;
    f.bottom = 22;
    f.x_lo = 0;
    f.x_hi = span;
    f.y_lo = p.min;
    f.y_hi = p.max;
    const auto yt = svg::nice_ticks(p.min, p.max, 3);
    f.y_lo = std::min(f.y_lo, yt.front());
    f.y_hi = std::max(f.y_hi, yt.back());
    const std::string_view model = stats.device_model(key.first);
    put(o, "<div class=\"small\"><h3>slave {}{}{}{} &middot; {}{}{}</h3>", key.first,
        model.empty() ? "" : " (", escaped(model), model.empty() ? "" : ")", escaped(key.second),
        p.unit.empty() ? "" : " &middot; ", escaped(p.unit));
    svg::open(o, f, fmt::format("slave {} {} over time", key.first, key.second), "point");
    svg::y_axis(o, f, yt, "");
    svg::x_axis(o, f, xt.ticks, xt.labels);
    const auto& ts = p.over_time;
    const double w = to_seconds(ts.width());
    const double off = to_seconds(ts.origin() - t0);
    Out band;
    Out line;
    bool started = false;
    for (std::size_t i = 0; i < ts.size(); ++i) {
      const PointBucket& b = ts[i];
      if (b.count == 0) continue;
      const double x0 = f.px(off + w * static_cast<double>(i));
      const double x1 = f.px(std::min(span, off + w * static_cast<double>(i + 1)));
      if (b.max > b.min) {
        put(band,
            "<rect class=\"band\" x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" "
            "height=\"{:.2f}\"/>",
            x0, f.py(b.max), std::max(x1 - x0, 0.8), f.py(b.min) - f.py(b.max));
      }
      put(line, "{}{:.2f},{:.2f} {:.2f},{:.2f}", started ? " L" : "M", x0, f.py(b.last), x1,
          f.py(b.last));
      started = true;
    }
    o.append(band);
    put(o, "<path class=\"val\" d=\"");
    o.append(line);
    put(o, "\"/>");
    svg::close(o);
    put(o, "<div class=\"note\">{} samples, {} changes, last {}{}{}</div></div>", p.samples,
        p.changes, p.last, p.unit.empty() ? "" : " ", escaped(p.unit));
  }
  put(o, "</div>");
  if (changing > kMaxPointCharts) {
    put(o, "<div class=\"note\">{} further changing points are listed in the table only.</div>",
        changing - kMaxPointCharts);
  }
  put(o,
      "<div class=\"scroll\"><table style=\"margin-top:12px\"><thead><tr><th "
      "class=\"l\">slave</th><th class=\"l\">"
      "point</th><th class=\"l\">unit</th><th>samples</th><th>changes</th><th>min</th>"
      "<th>max</th><th>last</th></tr></thead><tbody>");
  for (const auto& [key, p] : stats.points()) {
    put(o,
        "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td>"
        "<td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
        key.first, escaped(key.second), escaped(p.unit), p.samples, p.changes, p.min, p.max,
        p.last);
  }
  put(o, "</tbody></table></div>");
  if (stats.points_overflow() > 0) {
    put(o, "<div class=\"note\">{} values of further points are not tabled.</div>",
        stats.points_overflow());
  }
  put(o, "</section>");
}

}  // namespace

void write_report_html(OutputStream& out, const TrafficStats& stats,
                       const std::vector<Finding>& findings) {
  Out o;
  put(o,
      "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\">"
      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
      "<title>rtuscope report: {}</title><style>{}</style></head><body>",
      escaped(stats.capture().source), kStyle);
  header(o, stats);
  put(o, "<main>");
  summary(o, stats);
  findings_section(o, findings, stats.totals().records > 0);
  timeline_chart(o, stats);
  utilisation_chart(o, stats);
  slave_table(o, stats);
  latency_histograms(o, stats);
  poll_table(o, stats);
  timing_section(o, stats);
  points_section(o, stats);
  put(o, "<footer>Generated by rtuscope {}. Self-contained: no scripts, nothing fetched.</footer>",
      RTUSCOPE_VERSION);
  put(o, "</main></body></html>\n");
  out.write(o);
}

}  // namespace rtu
