#include <fmt/format.h>

#include "core/function_codes.hpp"
#include "report/report_writers.hpp"
#include "report/timing_note.hpp"

namespace rtu {

namespace {

using Out = fmt::memory_buffer;

template <typename... Args>
void line(Out& o, fmt::format_string<Args...> f, Args&&... args) {
  fmt::format_to(std::back_inserter(o), f, std::forward<Args>(args)...);
  o.push_back('\n');
}

std::string latency_text(const LogHistogram& h) {
  if (h.empty()) return "-";
  return fmt::format("{:.1f}/{:.1f}/{:.1f}/{:.1f}/{:.1f}", to_millis(h.min()),
                     to_millis(h.quantile(0.5)), to_millis(h.quantile(0.95)),
                     to_millis(h.quantile(0.99)), to_millis(h.max()));
}

// "2 after the master's frames, 3 after slave 4's": who sent the frames that the framer's
// turnaround glitches followed.
std::string glitch_senders(const TrafficStats& stats) {
  std::string out = fmt::format("{} after the master's frames", stats.master_turnaround_glitches());
  for (unsigned a = 1; a < 256; ++a) {
    const SlaveStats* s = stats.slave(static_cast<std::uint8_t>(a));
    if (s != nullptr && s->turnaround_glitches_sent > 0) {
      out += fmt::format(", {} after slave {}'s", s->turnaround_glitches_sent, a);
    }
  }
  return out;
}

// "; 46 on turnaround glitches": line errors that are the undriven bus, not a device's.
std::string glitch_line_errors(const Totals& t) {
  const std::uint64_t n = t.glitch_line_errors.records;
  return n == 0 ? std::string() : fmt::format("; {} on turnaround glitches", n);
}

// "; 46 with a framing error or break": the framer's glitches where the bus floated.
std::string flagged_glitch_line_errors(const Totals& t) {
  const std::uint64_t n = t.turnaround_glitch_line_errors;
  return n == 0 ? std::string() : fmt::format("; {} with a framing error or break", n);
}

}  // namespace

void write_report_text(OutputStream& out, const TrafficStats& stats,
                       const std::vector<Finding>& findings) {
  Out o;
  const CaptureInfo& info = stats.capture();
  const Totals& t = stats.totals();
  line(o, "rtuscope report: {}", info.source);
  line(o, "line {}, {}", info.line.describe(), timing_note(info));
  for (const std::string& w : info.warnings) line(o, "warning: {}", w);
  line(o, "");
  line(o, "TOTALS");
  line(o, "  duration          {:.3f} s", to_seconds(t.duration()));
  line(o, "  frames            {} ({} requests, {} responses, {} broadcasts)", t.frames, t.requests,
       t.responses, t.broadcasts);
  line(o, "  bytes             {} ({} noise bytes in {} records)", t.bytes, t.noise_bytes,
       t.noise_records);
  line(o, "  bus utilisation   {:.2f}%", t.utilisation() * 100.0);
  line(o, "  crc errors        {}", t.issues[IssueId::kCrc]);
  line(o, "  exceptions        {}", t.exceptions);
  line(o, "  timeouts          {} ({} late responses)", t.timeouts, t.issues[IssueId::kLate]);
  line(o, "  damaged requests  {} (unanswered; not counted as timeouts)", t.damaged_requests);
  line(o, "  unsolicited       {} ({} from the wrong slave)", t.issues[IssueId::kUnsolicited],
       t.issues[IssueId::kWrongSlave]);
  line(o, "  line errors       {} ({} parity, {} framing, {} break, {} overrun){}",
       t.line_error_records, t.parity_errors, t.framing_errors, t.breaks, t.overruns,
       glitch_line_errors(t));
  line(o, "  timing resolution {}", resolution_text(info));
  line(o, "");

  line(o, "FINDINGS");
  if (findings.empty() && t.records > 0) {
    line(o, "  none: nothing in this capture points to a problem");
  } else if (findings.empty()) {
    line(o, "  none: the capture holds no traffic to judge");
  }
  for (std::size_t i = 0; i < findings.size(); ++i) {
    const Finding& f = findings[i];
    line(o, "  {}. [{}] {}: {}", i + 1, severity_name(f.severity), f.key, f.summary);
    line(o, "     likely cause: {}", f.cause);
  }
  line(o, "");

  line(o, "SLAVES  latency ms = min/p50/p95/p99/max");
  line(o, "  {:>5} {:<10} {:>8} {:>8} {:>6} {:>8} {:>7} {:>5} {:>6}  {}", "slave", "device",
       "requests", "answers", "exc", "timeouts", "damaged", "crc", "unsol", "latency ms");
  bool any_identified = false;
  for (unsigned a = 1; a < 256; ++a) {
    const SlaveStats* s = stats.slave(static_cast<std::uint8_t>(a));
    if (s == nullptr) continue;
    const auto address = static_cast<std::uint8_t>(a);
    const std::string_view model = stats.device_model(address);
    const bool identified = stats.device_model_identified(address);
    any_identified = any_identified || identified;
    line(o, "  {:>5} {:<10} {:>8} {:>8} {:>6} {:>8} {:>7} {:>5} {:>6}  {}", a,
         model.empty() ? "-" : fmt::format("{}{}", model, identified ? "*" : ""), s->requests,
         s->responses, s->exceptions, s->timeouts, s->damaged_requests, s->issues[IssueId::kCrc],
         s->issues[IssueId::kUnsolicited], latency_text(s->latency));
    for (const auto& [code, n] : s->exception_codes) {
      line(o, "        exception {:02X} {} ×{}", code, stats.exception_name(address, code), n);
    }
    const std::string issues = issue_counts_text(s->issues);
    if (!issues.empty()) line(o, "        issues: {}", issues);
    if (s->latency_unseen > 0) {
      line(o,
           "        latency not seen for {} answers: each came in the read that ended its request",
           s->latency_unseen);
    }
  }
  if (any_identified) {
    line(o, "  * device identified from the traffic; name it with --device ADDR=MODEL or --bus");
  }
  if (const auto& sample = stats.identification()) line(o, "  {}", describe(*sample));
  line(o, "");

  line(o, "POLL PERIODS (per request kind)");
  line(o, "  {:>5} {:<28} {:>7} {:>7} {:>10} {:>10} {:>10}", "slave", "request", "count", "answers",
       "period p50", "min", "max");
  for (const auto& [kind, k] : stats.request_kinds()) {
    const std::string what =
        kind.has_range ? fmt::format("{} 0x{:04X} ×{}", function_short_name(kind.function),
                                     kind.addr, kind.qty)
                       : std::string(function_short_name(kind.function));
    if (k.period.empty()) {
      line(o, "  {:>5} {:<28} {:>7} {:>7} {:>10} {:>10} {:>10}", kind.slave, what, k.count,
           k.responses, "-", "-", "-");
    } else {
      line(o, "  {:>5} {:<28} {:>7} {:>7} {:>8.1f}ms {:>8.1f}ms {:>8.1f}ms", kind.slave, what,
           k.count, k.responses, to_millis(k.period.quantile(0.5)), to_millis(k.period.min()),
           to_millis(k.period.max()));
    }
  }
  if (stats.request_kinds_overflow() > 0) {
    line(o, "  ({} requests of further kinds not tabled)", stats.request_kinds_overflow());
  }
  line(o, "");

  line(o, "TIMING");
  const std::uint64_t unseen = stats.all_latencies_unseen();
  line(o, "  slave turnaround (latency) ms  {}{}", latency_text(stats.all_latencies()),
       unseen > 0 ? fmt::format(" (not seen for {} answers in their request's read)", unseen) : "");
  line(o, "  master turnaround ms           {}", latency_text(stats.master_turnaround()));
  line(o, "  t1.5 pauses inside frames      {}{}", t.issues[IssueId::kT15],
       stats.t15_observable() ? "" : " (not observable in this capture)");
  line(o, "  t3.5 violations                {}{}", t.issues[IssueId::kT35],
       stats.t35_observable() ? "" : " (not observable in this capture)");
  line(o, "  driver glitches at turnaround  {} ({}{})", t.turnaround_glitch_records,
       glitch_senders(stats), flagged_glitch_line_errors(t));
  out.write(o);
}

std::string issue_counts_text(const IssueCounts& counts) {
  std::string out;
  counts.for_each([&](IssueId id, std::uint64_t n) {
    fmt::format_to(std::back_inserter(out), "{}{} ×{}", out.empty() ? "" : ", ", issue_info(id).key,
                   n);
  });
  return out;
}

}  // namespace rtu
