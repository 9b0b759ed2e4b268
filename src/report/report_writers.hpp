#pragma once
// Renderings of a finished TrafficStats and its findings: text for a person, JSON for
// scripts, HTML for a customer. All three say the same numbers.
//
// JSON keys (public; add, never rename):
//   capture   {source, baud, parity, stop_bits, t1_5_ms, t3_5_ms, timing_resolution_ms (what
//              the timestamps could show over the whole capture), timing_resolution_start_ms
//              (what decoding started from: declared, chosen or estimated),
//              timing_resolution_learned (the reads showed the coarser one while decoding),
//              per_byte_timing, response_timeout_ms, timing_note}
//   totals    {start, end (seconds, input clock), duration_s, records, frames, requests,
//              responses, broadcasts, unknown_role, bytes, noise_records, noise_bytes,
//              bus_utilisation_pct, crc_errors, exceptions, timeouts (intact requests
//              unanswered), damaged_requests (damaged requests unanswered), late_responses,
//              unsolicited, wrong_slave, issues {key: records carrying it, for every issue key
//              counted, device keys such as scale_unknown included}, line_errors {records, parity,
//              framing, break, overrun, on_turnaround_glitches (records among them that are
//              turnaround glitches of either kind)}, t1_5_pauses, t3_5_violations,
//              timing_resolution_ms, slaves, request_kinds, request_kinds_overflow, points,
//              points_overflow}
//   slaves    {"<addr>": {device (model, null when unknown), device_model_source
//              ("configured" by --device/--bus, "identified" from the traffic, null), requests,
//              responses, exceptions, exceptions_by_code [{code, name (the device map's own meaning
//              where it has one), count}], timeouts, damaged_requests, late_responses,
//              crc_errors, unsolicited,
//              wrong_slave, issues {key: count, as in totals, over its frames},
//              after_next_request, frames, bytes, line_errors, latency_ms {min, p50,
//              p95, p99, max, mean} (null when no answer was timed), latency_samples,
//              function_codes [{fc, name, count}], poll_periods [{fc, function, addr, qty (null for
//              functions without a range), count, responses, exceptions, timeouts, period_ms {min,
//              p50, p95, max} (null below two requests)}], timing {t1_5_pauses_requests,
//              t1_5_pauses_responses, t3_5_responses_too_soon, t3_5_requests_too_soon,
//              turnaround_glitches, turnaround_glitch_sent (framer-flagged glitches after
//              its responses), turnaround_glitch_sent_line_errors}, timeout_fit [{timeout_ms,
//              lost, lost_pct}]}}
//   identification  {frames_wanted (--identify-frames; 0 for the whole capture), frames,
//              noise_bytes (what it looked at), ended ("enough", "capture_end", or "held_bound":
//              the records held for the decoding meanwhile reached their 24 MB bound, so the
//              models rest on fewer frames than were asked for)} | null (it did not run)
//   timing    {t1_5_observable, t3_5_observable, t1_5_pauses, t3_5_violations,
//              slave_turnaround_ms {min, p50, p95, p99, max, mean} | null,
//              master_turnaround_ms {...} | null (across turnaround glitches),
//              turnaround_glitches {after_requests, after_responses, bytes_00, bytes_ff,
//              line_errors} (lone 0x00/0xFF the framer did not flag), turnaround_glitch
//              {records, bytes, from_master, line_errors, from_master_line_errors} (noise
//              the framer flagged `turnaround_glitch`; never the same records as the former)}
//   findings  [{key, severity, slave (null), summary, cause, evidence {name: number},
//              units {name: unit}}] ranked, most important first
//   timeline  {start (s), bucket_s, frames [], requests [], responses [], crc_errors [],
//              exceptions [], timeouts [], noise_bytes [], line_errors [],
//              issues {key: [] for every issue key counted in the capture},
//              utilisation_pct []} one entry per bucket, up to the capture's end
//   points    [{slave, point, unit, samples, changes, first, min, max, last}]
#include <vector>

#include "core/output_stream.hpp"
#include "report/findings.hpp"
#include "report/traffic_stats.hpp"

namespace rtu {

void write_report_text(OutputStream& out, const TrafficStats& stats,
                       const std::vector<Finding>& findings);
void write_report_json(OutputStream& out, const TrafficStats& stats,
                       const std::vector<Finding>& findings);
// One self-contained HTML file: inline CSS and SVG, no scripts, nothing fetched.
void write_report_html(OutputStream& out, const TrafficStats& stats,
                       const std::vector<Finding>& findings);

// "crc ×3, scale_unknown ×12": every issue key counted, in catalogue order (text and HTML).
std::string issue_counts_text(const IssueCounts& counts);

}  // namespace rtu
