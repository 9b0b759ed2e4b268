#include "report/findings.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "core/function_codes.hpp"

namespace rtu {

namespace {

double ratio(std::uint64_t part, std::uint64_t whole) {
  return whole == 0 ? 0.0 : static_cast<double>(part) / static_cast<double>(whole);
}

// "0.4%", "12%", "0.03%": enough digits to tell a small share from none.
std::string pct(double fraction) {
  const double p = fraction * 100.0;
  if (p == 0.0) return "0%";
  if (p < 0.1) return fmt::format("{:.2f}%", p);
  if (p < 10.0) return fmt::format("{:.1f}%", p);
  return fmt::format("{:.0f}%", p);
}

double ms(Nanos t) {
  return to_millis(t);
}

struct Builder {
  std::vector<Finding> out;

  Finding& add(std::string key, Severity severity, std::optional<std::uint8_t> slave,
               double weight) {
    Finding f;
    f.key = std::move(key);
    f.severity = severity;
    f.slave = slave;
    f.weight = weight;
    out.push_back(std::move(f));
    return out.back();
  }
};

void ev(Finding& f, std::string name, double value, std::string unit = {}) {
  f.evidence.push_back(Evidence{std::move(name), value, std::move(unit)});
}

template <typename Fn>
void for_each_slave(const TrafficStats& stats, Fn&& fn) {
  for (unsigned a = 1; a < 256; ++a) {
    if (const SlaveStats* s = stats.slave(static_cast<std::uint8_t>(a))) {
      fn(static_cast<std::uint8_t>(a), *s);
    }
  }
}

// CRC errors: one slave, long frames, or everywhere. A slave is "the" culprit when it has at
// least 3 bad frames, 60% of all bad frames, and an error rate 3× that of the other slaves.
void crc_rules(const TrafficStats& stats, Builder& b) {
  const Totals& t = stats.totals();
  if (t.issues[IssueId::kCrc] < 3) return;
  bool explained = false;
  for_each_slave(stats, [&](std::uint8_t a, const SlaveStats& s) {
    if (s.issues[IssueId::kCrc] < 3 ||
        ratio(s.issues[IssueId::kCrc], t.issues[IssueId::kCrc]) < 0.6)
      return;
    const double rate = ratio(s.issues[IssueId::kCrc], s.frames);
    const double others =
        ratio(t.issues[IssueId::kCrc] - s.issues[IssueId::kCrc], t.frames - s.frames);
    if (others > 0.0 && rate < 3.0 * others) return;
    explained = true;
    Finding& f = b.add("crc_errors_one_slave", Severity::kError, a, rate);
    f.summary = fmt::format(
        "{} of {} CRC errors ({}) are on slave {}'s frames: {} of its frames fail, {} of the "
        "other slaves' frames",
        s.issues[IssueId::kCrc], t.issues[IssueId::kCrc],
        pct(ratio(s.issues[IssueId::kCrc], t.issues[IssueId::kCrc])), a, pct(rate), pct(others));
    f.cause = fmt::format(
        "cabling, termination or bias on slave {}'s drop, or its transmitter, corrupts its "
        "frames",
        a);
    ev(f, "slave_crc_errors", static_cast<double>(s.issues[IssueId::kCrc]));
    ev(f, "slave_frames", static_cast<double>(s.frames));
    ev(f, "slave_error_rate", rate * 100.0, "%");
    ev(f, "other_error_rate", others * 100.0, "%");
  });

  // Long frames (≥ 64 bytes) fail at ≥ 3× the rate of short ones (< 16 bytes).
  const std::uint64_t long_frames = t.frames_by_length[2] + t.frames_by_length[3];
  const std::uint64_t long_bad = t.crc_by_length[2] + t.crc_by_length[3];
  const double short_rate = ratio(t.crc_by_length[0], t.frames_by_length[0]);
  const double long_rate = ratio(long_bad, long_frames);
  if (long_bad >= 3 && long_rate >= 3.0 * short_rate && t.frames_by_length[0] >= 10) {
    explained = true;
    Finding& f = b.add("crc_errors_long_frames", Severity::kWarning, std::nullopt, long_rate);
    f.summary = fmt::format(
        "{} of frames of 64 bytes or more fail the CRC against {} of frames under 16 bytes",
        pct(long_rate), pct(short_rate));
    f.cause =
        "bit errors hit a share of all bytes, so long frames fail most: noise pickup, missing "
        "termination (reflections) or marginal signal levels on the bus";
    ev(f, "long_frames", static_cast<double>(long_frames));
    ev(f, "long_crc_errors", static_cast<double>(long_bad));
    ev(f, "long_error_rate", long_rate * 100.0, "%");
    ev(f, "short_error_rate", short_rate * 100.0, "%");
  }

  if (!explained) {
    const double rate = ratio(t.issues[IssueId::kCrc], t.frames);
    Finding& f = b.add("crc_errors_spread", Severity::kWarning, std::nullopt, rate);
    f.summary = fmt::format("{} CRC errors in {} frames ({}), spread over slaves and lengths",
                            t.issues[IssueId::kCrc], t.frames, pct(rate));
    f.cause = "interference on the whole bus: check shield grounding, termination and bias";
    ev(f, "crc_errors", static_cast<double>(t.issues[IssueId::kCrc]));
    ev(f, "frames", static_cast<double>(t.frames));
    ev(f, "error_rate", rate * 100.0, "%");
  }
}

// What a framing error or break on these glitches adds: nobody drove the line (an undriven
// line reads low), so bias is missing rather than only a driver being slow. Empty when none.
std::string floating_bus_note(std::uint64_t with_line_errors) {
  if (with_line_errors == 0) return {};
  return fmt::format(
      "; {} of them carry a framing error or break, the undriven line read as low: the bus "
      "floats at turnaround, so the fail-safe bias is missing",
      with_line_errors);
}

// 0x00/0xFF bytes after a turnaround that the framer did not flag (it flags lone bytes within
// about a character of a frame: sender_glitch_rule): at least 3 of them. The two rules count
// disjoint records and together make up the turnaround glitches.
void glitch_rule(const TrafficStats& stats, Builder& b) {
  std::uint64_t after_request = 0;
  std::uint8_t worst = 0;
  std::uint64_t worst_count = 0;
  for_each_slave(stats, [&](std::uint8_t a, const SlaveStats& s) {
    after_request += s.glitches_after_request;
    if (s.glitches_after_request > worst_count) {
      worst = a;
      worst_count = s.glitches_after_request;
    }
  });
  const std::uint64_t total = after_request + stats.glitches_after_response();
  if (total < 3) return;
  const Totals& t = stats.totals();
  const double share = ratio(total, t.requests + t.responses);
  Finding& f = b.add("turnaround_glitches", Severity::kWarning, std::nullopt, share);
  f.summary = fmt::format(
      "{} lone 0x00/0xFF bytes right after a turnaround ({} after requests, {} after "
      "responses; {} × 0x00, {} × 0xFF){}",
      total, after_request, stats.glitches_after_response(), stats.glitch_bytes_00(),
      stats.glitch_bytes_ff(),
      worst_count > 0 ? fmt::format(", most before slave {}'s answer ({})", worst, worst_count)
                      : std::string());
  if (t.turnaround_glitch_records > 0) {
    f.summary += fmt::format(
        "; besides the {} lone bytes right after a frame (turnaround_glitch), not counted here",
        t.turnaround_glitch_records);
  }
  const std::uint64_t line_errors = stats.glitches_after_turnaround_line_errors();
  f.cause =
      "missing bias (fail-safe) resistors or a slow driver enable: the line floats while no "
      "driver holds it and a receiver sees a false start bit" +
      floating_bus_note(line_errors);
  ev(f, "glitches", static_cast<double>(total));
  ev(f, "after_requests", static_cast<double>(after_request));
  ev(f, "after_responses", static_cast<double>(stats.glitches_after_response()));
  ev(f, "bytes_00", static_cast<double>(stats.glitch_bytes_00()));
  ev(f, "bytes_ff", static_cast<double>(stats.glitch_bytes_ff()));
  ev(f, "line_errors", static_cast<double>(line_errors));
}

// Who sent the frame a turnaround glitch followed, for sentences.
std::string sender_name(std::optional<std::uint8_t> slave) {
  return slave ? fmt::format("slave {}", *slave) : std::string("the master");
}

// One sender's turnaround glitches: how many, how many with line errors, and the sender's own
// frames a glitch can follow (its requests or its responses).
struct SenderGlitches {
  std::optional<std::uint8_t> slave;  // empty: the master
  std::uint64_t glitches = 0;
  std::uint64_t line_errors = 0;
  std::uint64_t frames = 0;
  std::string frames_name;
};

// Without line errors the glitch is the sender's driver letting go untidily; with framing
// errors or breaks the line was left undriven, which bias should have held idle.
std::string sender_glitch_cause(const SenderGlitches& g) {
  const std::string sender = sender_name(g.slave);
  if (g.line_errors == 0) {
    return fmt::format(
        "{}'s RS-485 driver/transceiver glitches at turnaround (driver-enable timing or "
        "missing bias/termination)",
        sender);
  }
  return fmt::format(
      "a framing error or break at turnaround means the bus floats when {}'s driver lets go: "
      "nobody holds the line idle, so the fail-safe bias resistors are missing (or too weak); "
      "{}'s driver-enable timing may add to it",
      sender, sender);
}

void sender_glitch_finding(Builder& b, const SenderGlitches& g) {
  const double share = std::min(1.0, ratio(g.glitches, g.frames));
  Finding& f = b.add("turnaround_glitch", Severity::kWarning, g.slave, share);
  f.summary = fmt::format(
      "{} lone bytes followed {}'s frames within about a character, after {} of its {} {}",
      g.glitches, sender_name(g.slave), pct(share), g.frames, g.frames_name);
  if (g.line_errors > 0) {
    f.summary += fmt::format("; {} with a framing error or break", g.line_errors);
  }
  f.cause = sender_glitch_cause(g);
  ev(f, "glitches", static_cast<double>(g.glitches));
  ev(f, g.frames_name, static_cast<double>(g.frames));
  ev(f, "share", share * 100.0, "%");
  ev(f, "line_errors", static_cast<double>(g.line_errors));
}

// Lone bytes the framer flagged `turnaround_glitch`, per sender: at least 3 from one sender.
// They are explained by their sender's turnaround, so neither the `noise` finding nor the
// line-error findings count them.
void sender_glitch_rule(const TrafficStats& stats, Builder& b) {
  const Totals& t = stats.totals();
  if (stats.master_turnaround_glitches() >= 3) {
    sender_glitch_finding(b,
                          {std::nullopt, stats.master_turnaround_glitches(),
                           stats.master_turnaround_glitch_line_errors(), t.requests, "requests"});
  }
  for_each_slave(stats, [&](std::uint8_t a, const SlaveStats& s) {
    if (s.turnaround_glitches_sent >= 3) {
      sender_glitch_finding(b, {a, s.turnaround_glitches_sent, s.turnaround_glitch_line_errors,
                                s.responses, "responses"});
    }
  });
}

// "slave 3 ×5, slave 7 ×2": the slaves with damaged requests, most first; `only` is the one
// slave when there is just one.
std::string damaged_by_slave(const TrafficStats& stats, std::optional<std::uint8_t>& only) {
  std::vector<std::pair<std::uint64_t, std::uint8_t>> counts;
  for_each_slave(stats, [&](std::uint8_t a, const SlaveStats& s) {
    if (s.damaged_requests > 0) counts.emplace_back(s.damaged_requests, a);
  });
  std::stable_sort(counts.begin(), counts.end(),
                   [](const auto& x, const auto& y) { return x.first > y.first; });
  only = counts.size() == 1 ? std::optional<std::uint8_t>(counts[0].second) : std::nullopt;
  std::string out;
  for (const auto& [n, a] : counts) {
    out += fmt::format("{}slave {} ×{}", out.empty() ? "" : ", ", a, n);
  }
  return out;
}

// Requests the wire damaged and that went unanswered: at least 3. They are kept out of the
// slaves' timeouts, since a slave must ignore a request it cannot read.
void damaged_request_rule(const TrafficStats& stats, Builder& b) {
  const Totals& t = stats.totals();
  if (t.damaged_requests < 3) return;
  std::optional<std::uint8_t> only;
  const std::string by_slave = damaged_by_slave(stats, only);
  const double share = std::min(1.0, ratio(t.damaged_requests, t.requests));
  Finding& f = b.add("damaged_requests", Severity::kWarning, only, share);
  f.summary = fmt::format(
      "{} requests arrived damaged (bad CRC, truncated or line errors) and went unanswered "
      "({}); they are not counted as the slaves' timeouts",
      t.damaged_requests, by_slave);
  f.cause =
      "the wire damaged the master's requests, so the slaves rightly ignored them; the slaves "
      "are not failing: look for noise, termination, bias or the master's transmitter";
  ev(f, "damaged_requests", static_cast<double>(t.damaged_requests));
  ev(f, "requests", static_cast<double>(t.requests));
  ev(f, "timeouts", static_cast<double>(t.timeouts));
}

// Requests while a response is due: ≥ 5 answers from this slave came after another request,
// and the time from its request to that other request varies by 2x or more between the 10th
// and 90th percentile. A master that gives up waits its timeout, the same every time; a
// second master's requests land anywhere in the first one's transactions.
void two_masters_rule(std::uint8_t a, const SlaveStats& s, Builder& b) {
  const LogHistogram& after = s.next_request_after;
  if (after.count() < 5) return;
  const Nanos low = after.quantile(0.1);
  const Nanos high = after.quantile(0.9);
  if (high < 2 * std::max<Nanos>(low, kNanosPerMilli)) return;
  Finding& f = b.add("two_masters", Severity::kError, a, ratio(after.count(), s.requests));
  f.summary = fmt::format(
      "{} times another request began while slave {}'s answer was due, {:.1f} to {:.1f} ms "
      "after its request (10th to 90th percentile), and its answer came after it",
      after.count(), a, ms(low), ms(high));
  f.cause =
      "two masters share the line (a second PLC, an HMI, a laptop left polling): a master "
      "that gave up would wait its timeout, about the same every time";
  ev(f, "requests_while_answer_due", static_cast<double>(after.count()));
  ev(f, "next_request_after_p10", ms(low), "ms");
  ev(f, "next_request_after_p90", ms(high), "ms");
}

void per_slave_rules(const TrafficStats& stats, Builder& b) {
  const Totals& t = stats.totals();
  const CaptureInfo& info = stats.capture();
  for_each_slave(stats, [&](std::uint8_t a, const SlaveStats& s) {
    // Pauses inside responses: only where a t1.5 silence is observable; ≥ 3 and ≥ 1%.
    if (stats.t15_observable() && s.t15_responses >= 3 &&
        ratio(s.t15_responses, s.responses) >= 0.01) {
      const double share = ratio(s.t15_responses, s.responses);
      Finding& f = b.add("pauses_in_responses", Severity::kWarning, a, share);
      f.summary = fmt::format(
          "{} of slave {}'s {} responses ({}) pause longer than t1.5 ({:.3f} ms) between bytes",
          s.t15_responses, a, s.responses, pct(share), ms(info.line.t1_5()));
      f.cause = fmt::format(
          "slave {}'s firmware stalls while sending; a strict master drops these frames as "
          "incomplete and may time out",
          a);
      ev(f, "responses_with_pause", static_cast<double>(s.t15_responses));
      ev(f, "responses", static_cast<double>(s.responses));
      ev(f, "t1_5", ms(info.line.t1_5()), "ms");
    }

    // Answers after the master moved on: ≥ 2.
    if (s.after_next_request >= 2) {
      const double share = ratio(s.after_next_request, s.requests);
      Finding& f = b.add("responses_after_next_request", Severity::kError, a, share);
      f.summary = fmt::format(
          "{} of slave {}'s responses arrived after the master had given up and sent its "
          "next request ({} of its requests timed out)",
          s.after_next_request, a, s.timeouts);
      f.cause =
          "the master's response timeout is shorter than this slave's latency, or a second "
          "master shares the bus";
      ev(f, "late_answers", static_cast<double>(s.after_next_request));
      ev(f, "timeouts", static_cast<double>(s.timeouts));
      if (!s.latency.empty()) ev(f, "latency_max", ms(s.latency.max()), "ms");
      two_masters_rule(a, s, b);
    } else if (s.issues[IssueId::kUnsolicited] >= 2) {
      const double share = ratio(s.issues[IssueId::kUnsolicited], s.responses);
      Finding& f = b.add("unsolicited_responses", Severity::kWarning, a, share);
      f.summary = fmt::format("{} responses from slave {} answered no request seen on the bus",
                              s.issues[IssueId::kUnsolicited], a);
      f.cause =
          "a second master (or a device answering for another address) talks on the bus, or "
          "the capture missed the requests";
      ev(f, "unsolicited", static_cast<double>(s.issues[IssueId::kUnsolicited]));
    }

    // Not answering at all, or sometimes: ≥ 3 timeouts. Shares are of the intact requests,
    // since only those have timeouts (damaged ones: damaged_request_rule).
    if (s.timeouts >= 3) {
      const double share = ratio(s.timeouts, s.intact_requests);
      const std::string_view requests = s.intact_requests == s.requests ? "" : "intact ";
      if (share >= 0.5) {
        Finding& f = b.add("slave_not_responding", Severity::kError, a, share);
        f.summary = fmt::format("slave {} left {} of its {} {}requests ({}) unanswered", a,
                                s.timeouts, s.intact_requests, requests, pct(share));
        f.cause = s.responses == 0
                      ? "no device answers at this address: it is off, disconnected, set to "
                        "another address, or uses other line settings"
                      : "the device answers only now and then: check its power, its line "
                        "settings and its drop";
        ev(f, "timeouts", static_cast<double>(s.timeouts));
        ev(f, "requests", static_cast<double>(s.requests));
        ev(f, "intact_requests", static_cast<double>(s.intact_requests));
        ev(f, "responses", static_cast<double>(s.responses));
      } else if (share >= 0.01) {
        Finding& f = b.add("slave_timeouts", Severity::kWarning, a, share);
        f.summary = fmt::format("slave {} missed {} of its {} {}requests ({})", a, s.timeouts,
                                s.intact_requests, requests, pct(share));
        f.cause = s.issues[IssueId::kLate] > 0 || s.after_next_request > 0
                      ? "its answers are sometimes slower than the master's timeout"
                      : "requests or answers are lost on the line (noise), or the device is "
                        "busy and drops requests";
        ev(f, "timeouts", static_cast<double>(s.timeouts));
        ev(f, "requests", static_cast<double>(s.requests));
        ev(f, "intact_requests", static_cast<double>(s.intact_requests));
      }
    }

    // Timeout fitting from the latencies of the answers that did arrive (≥ 10 of them),
    // where the tail reaches past 100 ms or the master did time out.
    if (s.latency.count() >= 10 && (s.lost_at[1] > 0 || s.issues[IssueId::kLate] > 0 ||
                                    s.timeouts > 0 || s.after_next_request > 0)) {
      std::size_t none = 0;
      while (none < kCandidateTimeoutsMs.size() && s.lost_at[none] > 0) ++none;
      const std::uint64_t n = s.latency.count();
      Finding& f =
          b.add("timeout_fit",
                s.issues[IssueId::kLate] > 0 || s.after_next_request > 0 ? Severity::kWarning
                                                                         : Severity::kInfo,
                a, ratio(s.issues[IssueId::kLate], n));
      const std::string tail = fmt::format("latency p99 {:.1f} ms, max {:.1f} ms over {} responses",
                                           ms(s.latency.quantile(0.99)), ms(s.latency.max()), n);
      if (none == kCandidateTimeoutsMs.size()) {
        f.summary = fmt::format(
            "even a master timeout of {} ms would have lost {} of slave {}'s responses ({})",
            kCandidateTimeoutsMs.back(), pct(ratio(s.lost_at.back(), n)), a, tail);
      } else if (none == 0) {
        f.summary = fmt::format("a master timeout of {} ms loses none of slave {}'s responses ({})",
                                kCandidateTimeoutsMs[0], a, tail);
      } else {
        f.summary = fmt::format(
            "a master timeout of {} ms would have lost {} of slave {}'s responses; {} ms loses "
            "none ({})",
            kCandidateTimeoutsMs[none - 1], pct(ratio(s.lost_at[none - 1], n)), a,
            kCandidateTimeoutsMs[none], tail);
        ev(f, "losing_timeout", static_cast<double>(kCandidateTimeoutsMs[none - 1]), "ms");
        ev(f, "lost_share", ratio(s.lost_at[none - 1], n) * 100.0, "%");
      }
      if (none < kCandidateTimeoutsMs.size()) {
        ev(f, "safe_timeout", static_cast<double>(kCandidateTimeoutsMs[none]), "ms");
      }
      f.cause = s.responses > 0 && s.timeouts > 0 && none == 0
                    ? "the slave answers fast when it answers: its timeouts are missing "
                      "answers, not slow ones"
                    : "the slave's latency has a long tail; a master timeout below the safe "
                      "value drops some of its answers";
      if (info.resolution_at_end() > kNanosPerMilli) {
        f.cause += fmt::format(" (latencies are known to ±{:.0f} ms in this capture)",
                               ms(info.resolution_at_end()));
      }
      ev(f, "responses", static_cast<double>(n));
      ev(f, "latency_p99", ms(s.latency.quantile(0.99)), "ms");
      ev(f, "latency_max", ms(s.latency.max()), "ms");
    }

    // Answers < t3.5 after the request: only where t3.5 is observable; ≥ 3.
    if (stats.t35_observable() && s.t35_responses >= 3) {
      const double share = ratio(s.t35_responses, s.responses);
      Finding& f = b.add("responses_too_soon", Severity::kWarning, a, share);
      f.summary = fmt::format(
          "slave {} started {} responses less than t3.5 ({:.3f} ms) after the request ended", a,
          s.t35_responses, ms(info.line.t3_5()));
      f.cause =
          "the slave's turnaround is shorter than the specification's frame gap; a master that "
          "still waits out t3.5 can miss the start of the answer";
      ev(f, "responses_too_soon", static_cast<double>(s.t35_responses));
      ev(f, "responses", static_cast<double>(s.responses));
    }
  });
  (void)t;
}

// " (besides 46 on turnaround glitches)": line errors these rules leave to the glitch ones.
std::string glitch_line_errors_note(const Totals& t) {
  const std::uint64_t n = t.glitch_line_errors.records;
  return n == 0 ? std::string() : fmt::format(" (besides {} on turnaround glitches)", n);
}

// Line errors where one slave's answer is due (≥ 3 records, ≥ 60% of all); otherwise spread.
// Line errors on turnaround glitches are the undriven bus, not a device's settings: they are
// left to the glitch findings and counted in neither rule.
void line_error_rules(const TrafficStats& stats, Builder& b) {
  const Totals& t = stats.totals();
  const LineErrorCounts le = t.line_errors_beyond_glitches();
  if (le.records < 3) return;
  bool explained = false;
  for_each_slave(stats, [&](std::uint8_t a, const SlaveStats& s) {
    if (s.line_errors < 3 || ratio(s.line_errors, le.records) < 0.6) return;
    explained = true;
    const double share = ratio(s.line_errors, le.records);
    Finding& f = b.add("line_errors_one_device", Severity::kError, a, share);
    f.summary = fmt::format(
        "{} of {} records with parity/framing errors ({}) fall where slave {} answers, with {} "
        "valid frames in between{}",
        s.line_errors, le.records, pct(share), a, t.valid_frames_between_line_errors,
        glitch_line_errors_note(t));
    f.cause =
        fmt::format("slave {} is set to another baud rate or parity than the rest of the bus", a);
    ev(f, "slave_line_errors", static_cast<double>(s.line_errors));
    ev(f, "line_error_records", static_cast<double>(le.records));
    ev(f, "valid_frames_between", static_cast<double>(t.valid_frames_between_line_errors));
  });
  if (explained || t.valid_frames_between_line_errors == 0) return;
  Finding& f = b.add("line_errors", Severity::kWarning, std::nullopt, ratio(le.records, t.records));
  f.summary = fmt::format(
      "{} records with line errors ({} parity, {} framing, {} break) with {} valid frames in "
      "between{}",
      le.records, le.parity, le.framing, le.breaks, t.valid_frames_between_line_errors,
      glitch_line_errors_note(t));
  f.cause =
      "a device with a baud rate or parity mismatch, or interference strong enough to flip "
      "bits";
  ev(f, "line_error_records", static_cast<double>(le.records));
  ev(f, "parity_errors", static_cast<double>(le.parity));
  ev(f, "framing_errors", static_cast<double>(le.framing));
  ev(f, "valid_frames_between", static_cast<double>(t.valid_frames_between_line_errors));
}

// A request kind with ≥ 3 exceptions making up ≥ 50% of its answers.
void exception_rule(const TrafficStats& stats, Builder& b) {
  for (const auto& [kind, k] : stats.request_kinds()) {
    if (k.exceptions < 3 || ratio(k.exceptions, k.responses) < 0.5) continue;
    std::uint8_t code = 0;
    std::uint64_t most = 0;
    for (const auto& [c, n] : k.exception_codes) {
      if (n > most) {
        code = c;
        most = n;
      }
    }
    const double share = ratio(k.exceptions, k.responses);
    Finding& f = b.add("exceptions_for_request", Severity::kWarning, kind.slave, share);
    const std::string what =
        kind.has_range ? fmt::format("FC{:02d} at 0x{:04X} ×{}", kind.function, kind.addr, kind.qty)
                       : fmt::format("FC{:02d}", kind.function);
    // A device with its own exception table (its map says so) means something else by 01-03.
    const bool vendor = stats.device_exception(kind.slave, code);
    const std::string_view name = stats.exception_name(kind.slave, code);
    f.summary = fmt::format("slave {} answered {} of {} requests {} with exception {} ({})",
                            kind.slave, k.exceptions, k.responses, what, code, name);
    if (vendor) {
      f.cause = fmt::format("the {} reports its own exception {:02X} ({}): see its manual",
                            stats.device_model(kind.slave), code, name);
    } else {
      f.cause = code == 0x02 || code == 0x01 || code == 0x03
                    ? "the master asks for registers or a function this device does not have: "
                      "its register map in the master does not fit the device"
                    : "the device refuses this request (busy or failing): see its manual for "
                      "this exception";
    }
    ev(f, "exceptions", static_cast<double>(k.exceptions));
    ev(f, "responses", static_cast<double>(k.responses));
    ev(f, "exception_code", code);
    ev(f, "function", kind.function);
    if (kind.has_range) ev(f, "address", kind.addr);
  }
}

void bus_rules(const TrafficStats& stats, Builder& b) {
  const Totals& t = stats.totals();
  const CaptureInfo& info = stats.capture();
  // Requests < t3.5 after the previous frame: only where observable; ≥ 3.
  std::uint64_t fast = 0;
  for_each_slave(stats, [&](std::uint8_t, const SlaveStats& s) { fast += s.t35_requests; });
  if (stats.t35_observable() && fast >= 3) {
    Finding& f =
        b.add("master_polls_too_fast", Severity::kWarning, std::nullopt, ratio(fast, t.requests));
    f.summary = fmt::format(
        "{} of {} requests ({}) started less than t3.5 ({:.3f} ms) after the previous frame", fast,
        t.requests, pct(ratio(fast, t.requests)), ms(info.line.t3_5()));
    f.cause =
        "the master sends the next request without the frame gap; slaves that wait for t3.5 "
        "of silence miss or merge these requests";
    ev(f, "requests_too_soon", static_cast<double>(fast));
    ev(f, "requests", static_cast<double>(t.requests));
  }

  // Requests seen twice in a row (request_echoes.hpp): ≥ 5, and half the requests or more,
  // since an echo is systematic where a coincidence is not.
  const RequestEchoes& echoes = stats.request_echoes();
  const std::uint64_t copies = echoes.echoes();
  const std::uint64_t originals = t.requests - copies;
  if (copies >= 5 && copies * 2 >= originals) {
    Finding& f = b.add("request_echo", Severity::kWarning, std::nullopt, ratio(copies, originals));
    f.summary = fmt::format(
        "{} of {} requests appear twice in a row, the copy at most {:.3f} ms after the first "
        "ended; {} of the first copies count as unanswered because of it",
        copies, originals, ms(echoes.longest_gap()), echoes.timeouts_on_first_copies());
    f.cause =
        "an RS-485 adapter hears its own transmission (its receiver stays on while it sends), or "
        "one port's transmit and receive lines are captured together: each pair is one request";
    ev(f, "echoed_requests", static_cast<double>(copies));
    ev(f, "requests", static_cast<double>(originals));
    ev(f, "longest_gap", ms(echoes.longest_gap()), "ms");
    ev(f, "timeouts_from_echo", static_cast<double>(echoes.timeouts_on_first_copies()));
  }

  // The busiest stretch of the capture (a timeline bucket) above 80% and at least 1 s long.
  const auto& tl = stats.timeline();
  double peak = 0.0;
  for (std::size_t i = 0; i < tl.size(); ++i) {
    if (tl.bucket_start(i) >= t.last_t) break;
    peak = std::max(peak, tl[i].busy_ns / static_cast<double>(tl.width()));
  }
  if (t.duration() >= kNanosPerSecond && tl.width() >= kNanosPerSecond / 4 && peak >= 0.8) {
    Finding& f =
        b.add("bus_busy", peak >= 0.95 ? Severity::kWarning : Severity::kInfo, std::nullopt, peak);
    f.summary = fmt::format(
        "the line carries bytes {} of the time overall and up to {} at its "
        "busiest",
        pct(t.utilisation()), pct(std::min(peak, 1.0)));
    f.cause =
        "polling is limited by the line rate: a faster baud rate, fewer or larger reads, or a "
        "slower poll cycle would leave room for retries";
    ev(f, "utilisation", t.utilisation() * 100.0, "%");
    ev(f, "peak_utilisation", std::min(peak, 1.0) * 100.0, "%");
  }

  // Noise beyond both kinds of turnaround glitches: ≥ 8 bytes and ≥ 0.1% of the bytes.
  // Bytes and stretches (records) are counted over the same records, like the totals' noise.
  const std::uint64_t other = stats.unexplained_noise_bytes();
  const std::uint64_t stretches = stats.unexplained_noise_records();
  if (other >= 8 && ratio(other, t.bytes) >= 0.001) {
    Finding& f = b.add("noise", Severity::kWarning, std::nullopt, ratio(other, t.bytes));
    f.summary = fmt::format("{} bytes ({} of all bytes) in {} stretches form no Modbus frame",
                            other, pct(ratio(other, t.bytes)), stretches);
    if (stretches != t.noise_records) {
      f.summary += fmt::format(
          " (of {} noise bytes in {} records; the other {} records are turnaround glitches)",
          t.noise_bytes, t.noise_records, t.noise_records - stretches);
    }
    f.cause =
        "interference, collisions between two talkers, or a device with other line settings "
        "produce bytes no frame explains";
    ev(f, "noise_bytes", static_cast<double>(other));
    ev(f, "noise_records", static_cast<double>(stretches));
    ev(f, "bytes", static_cast<double>(t.bytes));
  }
}

}  // namespace

std::vector<Finding> find_problems(const TrafficStats& stats) {
  Builder b;
  crc_rules(stats, b);
  glitch_rule(stats, b);
  sender_glitch_rule(stats, b);
  damaged_request_rule(stats, b);
  per_slave_rules(stats, b);
  line_error_rules(stats, b);
  exception_rule(stats, b);
  bus_rules(stats, b);
  std::stable_sort(b.out.begin(), b.out.end(), [](const Finding& x, const Finding& y) {
    if (x.severity != y.severity) return x.severity > y.severity;
    if (x.weight != y.weight) return x.weight > y.weight;
    if (x.key != y.key) return x.key < y.key;
    return x.slave.value_or(0) < y.slave.value_or(0);
  });
  return b.out;
}

}  // namespace rtu
