#include <fmt/format.h>

#include <optional>

#include "core/function_codes.hpp"
#include "core/json_writer.hpp"
#include "core/time_format.hpp"
#include "report/report_writers.hpp"
#include "report/timing_note.hpp"

namespace rtu {

namespace {

// "issues": {"crc": 3, "scale_unknown": 12, ...}: every key counted at least once, in
// catalogue order, device keys included.
void write_issue_counts(JsonWriter& j, const IssueCounts& counts) {
  j.key("issues");
  j.begin_object();
  counts.for_each([&](IssueId id, std::uint64_t n) { j.field(issue_info(id).key, n); });
  j.end_object();
}

void write_ms(JsonWriter& j, Nanos t) {
  j.value_fixed(to_millis(t), 3);
}

void write_percentiles(JsonWriter& j, const LogHistogram& h) {
  if (h.empty()) {
    j.null();
    return;
  }
  j.begin_object();
  j.key("min");
  write_ms(j, h.min());
  j.key("p50");
  write_ms(j, h.quantile(0.50));
  j.key("p95");
  write_ms(j, h.quantile(0.95));
  j.key("p99");
  write_ms(j, h.quantile(0.99));
  j.key("max");
  write_ms(j, h.max());
  j.key("mean");
  j.value_fixed(h.mean() / 1e6, 3);
  j.end_object();
}

void write_seconds(JsonWriter& j, Nanos t) {
  append_seconds(j.raw_value_buffer(), t, 9);
}

void write_capture(JsonWriter& j, const CaptureInfo& info) {
  j.key("capture");
  j.begin_object();
  j.field("source", std::string_view(info.source));
  j.field("baud", info.line.baud);
  const char parity = parity_letter(info.line.parity);
  j.field("parity", std::string_view(&parity, 1));
  j.field("stop_bits", static_cast<unsigned>(info.line.stop_bits));
  j.key("t1_5_ms");
  write_ms(j, info.line.t1_5());
  j.key("t3_5_ms");
  write_ms(j, info.line.t3_5());
  j.key("timing_resolution_ms");
  write_ms(j, info.resolution_at_end());
  // What decoding started from (declared or estimated): below the above where the reads
  // showed coarser timing while decoding (timing_resolution_learned).
  j.key("timing_resolution_start_ms");
  write_ms(j, info.timing_resolution);
  j.field("timing_resolution_learned", info.learned_resolution != kUnknownTime);
  j.field("per_byte_timing", info.per_byte_timing);
  j.key("response_timeout_ms");
  write_ms(j, info.response_timeout);
  const std::string note = timing_note(info);
  j.field("timing_note", std::string_view(note));
  j.key("warnings");
  j.begin_array();
  for (const std::string& w : info.warnings) j.value(std::string_view(w));
  j.end_array();
  j.end_object();
}

std::size_t slave_count(const TrafficStats& stats) {
  std::size_t n = 0;
  for (unsigned a = 1; a < 256; ++a)
    if (stats.slave(static_cast<std::uint8_t>(a)) != nullptr) ++n;
  return n;
}

void write_totals(JsonWriter& j, const TrafficStats& stats) {
  const Totals& t = stats.totals();
  j.key("totals");
  j.begin_object();
  j.key("start");
  if (t.first_t == kUnknownTime)
    j.null();
  else
    write_seconds(j, t.first_t);
  j.key("end");
  if (t.first_t == kUnknownTime)
    j.null();
  else
    write_seconds(j, t.last_t);
  j.key("duration_s");
  j.value_fixed(to_seconds(t.duration()), 6);
  j.field("records", t.records);
  j.field("frames", t.frames);
  j.field("requests", t.requests);
  j.field("responses", t.responses);
  j.field("broadcasts", t.broadcasts);
  j.field("unknown_role", t.unknown_role);
  j.field("bytes", t.bytes);
  j.field("noise_records", t.noise_records);
  j.field("noise_bytes", t.noise_bytes);
  j.key("bus_utilisation_pct");
  j.value_fixed(t.utilisation() * 100.0, 2);
  j.field("crc_errors", t.issues[IssueId::kCrc]);
  j.field("exceptions", t.exceptions);
  j.field("timeouts", t.timeouts);
  j.field("damaged_requests", t.damaged_requests);
  j.field("late_responses", t.issues[IssueId::kLate]);
  j.field("unsolicited", t.issues[IssueId::kUnsolicited]);
  j.field("wrong_slave", t.issues[IssueId::kWrongSlave]);
  write_issue_counts(j, t.issues);
  j.key("line_errors");
  j.begin_object();
  j.field("records", t.line_error_records);
  j.field("parity", t.parity_errors);
  j.field("framing", t.framing_errors);
  j.field("break", t.breaks);
  j.field("overrun", t.overruns);
  // Of those records, the ones on turnaround glitches (the line-error findings leave them out).
  j.field("on_turnaround_glitches", t.glitch_line_errors.records);
  j.end_object();
  j.field("t1_5_pauses", t.issues[IssueId::kT15]);
  j.field("t3_5_violations", t.issues[IssueId::kT35]);
  j.key("timing_resolution_ms");
  write_ms(j, stats.capture().resolution_at_end());
  j.field("slaves", static_cast<std::uint64_t>(slave_count(stats)));
  j.field("request_kinds", static_cast<std::uint64_t>(stats.request_kinds().size()));
  j.field("request_kinds_overflow", stats.request_kinds_overflow());
  j.field("points", static_cast<std::uint64_t>(stats.points().size()));
  j.field("points_overflow", stats.points_overflow());
  j.end_object();
}

void write_slave(JsonWriter& j, const TrafficStats& stats, std::uint8_t a, const SlaveStats& s) {
  j.begin_object();
  j.key("device");
  const std::string_view model = stats.device_model(a);
  if (model.empty())
    j.null();
  else
    j.value(model);
  j.key("device_model_source");
  if (model.empty())
    j.null();
  else
    j.value(std::string_view(stats.device_model_identified(a) ? "identified" : "configured"));
  j.field("requests", s.requests);
  j.field("responses", s.responses);
  j.field("exceptions", s.exceptions);
  j.key("exceptions_by_code");
  j.begin_array();
  for (const auto& [code, n] : s.exception_codes) {
    j.begin_object();
    j.field("code", static_cast<unsigned>(code));
    j.field("name", stats.exception_name(a, code));
    j.field("count", n);
    j.end_object();
  }
  j.end_array();
  j.field("timeouts", s.timeouts);
  j.field("damaged_requests", s.damaged_requests);
  j.field("late_responses", s.issues[IssueId::kLate]);
  j.field("crc_errors", s.issues[IssueId::kCrc]);
  j.field("unsolicited", s.issues[IssueId::kUnsolicited]);
  j.field("wrong_slave", s.issues[IssueId::kWrongSlave]);
  write_issue_counts(j, s.issues);
  j.field("after_next_request", s.after_next_request);
  j.field("frames", s.frames);
  j.field("bytes", s.bytes);
  j.field("line_errors", s.line_errors);
  j.key("latency_ms");
  write_percentiles(j, s.latency);
  j.field("latency_samples", s.latency.count());
  j.field("latency_unseen", s.latency_unseen);
  j.key("function_codes");
  j.begin_array();
  for (const auto& [f, n] : s.functions) {
    j.begin_object();
    j.field("fc", static_cast<unsigned>(f));
    j.field("name", function_name(f));
    j.field("count", n);
    j.end_object();
  }
  j.end_array();
  j.key("poll_periods");
  j.begin_array();
  for (const auto& [kind, k] : stats.request_kinds()) {
    if (kind.slave != a) continue;
    j.begin_object();
    j.field("fc", static_cast<unsigned>(kind.function));
    j.field("function", function_name(kind.function));
    j.key("addr");
    if (kind.has_range)
      j.value(static_cast<unsigned>(kind.addr));
    else
      j.null();
    j.key("qty");
    if (kind.has_range)
      j.value(static_cast<unsigned>(kind.qty));
    else
      j.null();
    j.field("count", k.count);
    j.field("responses", k.responses);
    j.field("exceptions", k.exceptions);
    j.field("timeouts", k.timeouts);
    j.key("period_ms");
    if (k.period.empty()) {
      j.null();
    } else {
      j.begin_object();
      j.key("min");
      write_ms(j, k.period.min());
      j.key("p50");
      write_ms(j, k.period.quantile(0.5));
      j.key("p95");
      write_ms(j, k.period.quantile(0.95));
      j.key("max");
      write_ms(j, k.period.max());
      j.end_object();
    }
    j.end_object();
  }
  j.end_array();
  j.key("timing");
  j.begin_object();
  j.field("t1_5_pauses_requests", s.t15_requests);
  j.field("t1_5_pauses_responses", s.t15_responses);
  j.field("t3_5_responses_too_soon", s.t35_responses);
  j.field("t3_5_requests_too_soon", s.t35_requests);
  j.field("turnaround_glitches", s.glitches_after_request);
  j.field("turnaround_glitch_sent", s.turnaround_glitches_sent);
  j.field("turnaround_glitch_sent_line_errors", s.turnaround_glitch_line_errors);
  j.end_object();
  j.key("timeout_fit");
  j.begin_array();
  if (!s.latency.empty()) {
    for (std::size_t i = 0; i < kCandidateTimeoutsMs.size(); ++i) {
      j.begin_object();
      j.field("timeout_ms", kCandidateTimeoutsMs[i]);
      j.field("lost", s.lost_at[i]);
      j.key("lost_pct");
      j.value_fixed(
          100.0 * static_cast<double>(s.lost_at[i]) / static_cast<double>(s.latency.count()), 3);
      j.end_object();
    }
  }
  j.end_array();
  j.end_object();
}

// null where identification did not run (--no-identify, or no device maps).
void write_identification(JsonWriter& j, const std::optional<IdentificationSample>& sample) {
  j.key("identification");
  if (!sample) {
    j.null();
    return;
  }
  j.begin_object();
  j.field("frames_wanted", sample->frames_wanted);
  j.field("frames", sample->frames);
  j.field("noise_bytes", sample->noise_bytes);
  j.field("ended", sample_end_name(sample->end));
  j.end_object();
}

void write_timing(JsonWriter& j, const TrafficStats& stats) {
  std::uint64_t after_requests = 0;
  for (unsigned a = 1; a < 256; ++a) {
    if (const auto* s = stats.slave(static_cast<std::uint8_t>(a))) {
      after_requests += s->glitches_after_request;
    }
  }
  j.key("timing");
  j.begin_object();
  j.field("t1_5_observable", stats.t15_observable());
  j.field("t3_5_observable", stats.t35_observable());
  j.field("t1_5_pauses", stats.totals().issues[IssueId::kT15]);
  j.field("t3_5_violations", stats.totals().issues[IssueId::kT35]);
  j.key("slave_turnaround_ms");
  write_percentiles(j, stats.all_latencies());
  j.field("slave_turnaround_unseen", stats.all_latencies_unseen());
  j.key("master_turnaround_ms");
  write_percentiles(j, stats.master_turnaround());
  j.key("turnaround_glitches");
  j.begin_object();
  j.field("after_requests", after_requests);
  j.field("after_responses", stats.glitches_after_response());
  j.field("bytes_00", stats.glitch_bytes_00());
  j.field("bytes_ff", stats.glitch_bytes_ff());
  j.field("line_errors", stats.glitches_after_turnaround_line_errors());
  j.end_object();
  // Lone bytes the framer flagged `turnaround_glitch`, by sender (slaves: per slave).
  j.key("turnaround_glitch");
  j.begin_object();
  j.field("records", stats.totals().turnaround_glitch_records);
  j.field("bytes", stats.totals().turnaround_glitch_bytes);
  j.field("from_master", stats.master_turnaround_glitches());
  j.field("line_errors", stats.totals().turnaround_glitch_line_errors);
  j.field("from_master_line_errors", stats.master_turnaround_glitch_line_errors());
  j.end_object();
  j.end_object();
}

void write_number(JsonWriter& j, double v) {
  if (v == static_cast<double>(static_cast<std::int64_t>(v)) && v > -1e15 && v < 1e15) {
    j.value(static_cast<std::int64_t>(v));
  } else {
    j.value_fixed(v, 3);
  }
}

void write_findings(JsonWriter& j, const std::vector<Finding>& findings) {
  j.key("findings");
  j.begin_array();
  for (const Finding& f : findings) {
    j.begin_object();
    j.field("key", std::string_view(f.key));
    j.field("severity", severity_name(f.severity));
    j.key("slave");
    if (f.slave)
      j.value(static_cast<unsigned>(*f.slave));
    else
      j.null();
    j.field("summary", std::string_view(f.summary));
    j.field("cause", std::string_view(f.cause));
    j.key("evidence");
    j.begin_object();
    for (const Evidence& e : f.evidence) {
      j.key(e.name);
      write_number(j, e.value);
    }
    j.end_object();
    j.key("units");
    j.begin_object();
    for (const Evidence& e : f.evidence) {
      if (!e.unit.empty()) j.field(e.name, std::string_view(e.unit));
    }
    j.end_object();
    j.end_object();
  }
  j.end_array();
}

// Buckets up to the one holding the capture's end.
std::size_t used_buckets(const TrafficStats& stats) {
  const auto& tl = stats.timeline();
  if (stats.totals().first_t == kUnknownTime) return 0;
  std::size_t n = 0;
  while (n < tl.size() && tl.bucket_start(n) < stats.totals().last_t) ++n;
  return std::max<std::size_t>(n, 1);
}

void write_timeline(JsonWriter& j, const TrafficStats& stats) {
  const auto& tl = stats.timeline();
  const std::size_t n = used_buckets(stats);
  j.key("timeline");
  j.begin_object();
  j.key("start");
  if (n == 0)
    j.null();
  else
    write_seconds(j, tl.origin());
  j.key("bucket_s");
  j.value_fixed(to_seconds(tl.width()), 6);
  auto column = [&](std::string_view name, auto get) {
    j.key(name);
    j.begin_array();
    for (std::size_t i = 0; i < n; ++i) j.value(get(tl[i]));
    j.end_array();
  };
  column("frames", [](const TrafficBucket& b) { return b.frames; });
  column("requests", [](const TrafficBucket& b) { return b.requests; });
  column("responses", [](const TrafficBucket& b) { return b.responses; });
  column("crc_errors", [](const TrafficBucket& b) { return b.issues[IssueId::kCrc]; });
  column("exceptions", [](const TrafficBucket& b) { return b.exceptions; });
  column("timeouts", [](const TrafficBucket& b) { return b.timeouts; });
  column("noise_bytes", [](const TrafficBucket& b) { return b.noise_bytes; });
  column("line_errors", [](const TrafficBucket& b) { return b.line_errors; });
  // One column per issue key seen anywhere in the capture.
  IssueCounts seen;
  for (std::size_t i = 0; i < n; ++i) seen.merge(tl[i].issues);
  j.key("issues");
  j.begin_object();
  seen.for_each([&](IssueId id, std::uint64_t) {
    column(issue_info(id).key, [id](const TrafficBucket& b) { return b.issues[id]; });
  });
  j.end_object();
  j.key("utilisation_pct");
  j.begin_array();
  for (std::size_t i = 0; i < n; ++i) {
    j.value_fixed(std::min(100.0, 100.0 * tl[i].busy_ns / static_cast<double>(tl.width())), 2);
  }
  j.end_array();
  j.end_object();
}

void write_points(JsonWriter& j, const TrafficStats& stats) {
  j.key("points");
  j.begin_array();
  for (const auto& [key, p] : stats.points()) {
    j.begin_object();
    j.field("slave", static_cast<unsigned>(key.first));
    j.field("point", std::string_view(key.second));
    j.field("unit", std::string_view(p.unit));
    j.field("samples", p.samples);
    j.field("changes", p.changes);
    j.key("first");
    j.value_double(p.first);
    j.key("min");
    j.value_double(p.min);
    j.key("max");
    j.value_double(p.max);
    j.key("last");
    j.value_double(p.last);
    j.end_object();
  }
  j.end_array();
}

}  // namespace

void write_report_json(OutputStream& out, const TrafficStats& stats,
                       const std::vector<Finding>& findings) {
  fmt::memory_buffer buf;
  JsonWriter j(buf);
  j.begin_object();
  write_capture(j, stats.capture());
  write_totals(j, stats);
  j.key("slaves");
  j.begin_object();
  for (unsigned a = 1; a < 256; ++a) {
    if (const SlaveStats* s = stats.slave(static_cast<std::uint8_t>(a))) {
      j.key(fmt::format("{}", a));
      write_slave(j, stats, static_cast<std::uint8_t>(a), *s);
    }
  }
  j.end_object();
  write_identification(j, stats.identification());
  write_timing(j, stats);
  write_findings(j, findings);
  write_timeline(j, stats);
  write_points(j, stats);
  j.end_object();
  buf.push_back('\n');
  out.write(buf);
}

}  // namespace rtu
