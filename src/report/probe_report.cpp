#include "report/probe_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/json_writer.hpp"

namespace rtu {
namespace {

// A winner needs a few CRC-valid frames that explain most of what was heard.
constexpr std::uint64_t kMinFrames = 2;
constexpr double kMinCleanShare = 0.5;

// Preference among settings a UART reads alike, by the Modbus rule (MODBUS over Serial
// Line §2.5.1: even parity is the default; without parity, two stop bits).
int modbus_rule_rank(const LineSettings& s) {
  if (s.parity == Parity::kEven) return 0;
  if (s.parity == Parity::kNone && s.stop_bits == 2) return 1;
  if (s.parity == Parity::kOdd) return 2;
  return 3;
}

double share(std::uint64_t part, std::uint64_t whole) {
  return whole == 0 ? 0.0 : static_cast<double>(part) / static_cast<double>(whole);
}

// Two framings at one baud that read the traffic equally well: nothing a UART reports
// tells them apart (the counts differ only by where each hearing began and ended).
bool reads_alike(const SettingEvidence& a, const SettingEvidence& b) {
  if (a.line.baud != b.line.baud || a.frames == 0 || b.frames == 0) return false;
  if (a.flagged_frame_bytes != 0 || b.flagged_frame_bytes != 0) return false;
  constexpr double kClose = 0.05;
  if (std::abs(a.clean_share() - b.clean_share()) > kClose) return false;
  if (std::abs(share(a.line_errors(), a.bytes) - share(b.line_errors(), b.bytes)) > kClose) {
    return false;
  }
  // Frames heard in a short dwell at a slow rate are few (ten a second at 1200 baud), so
  // two hearings of one traffic may differ by a quarter in their rate by chance alone.
  return std::min(a.score(), b.score()) >= 0.5 * std::max(a.score(), b.score());
}

std::string evidence_line(const SettingEvidence& e) {
  return fmt::format(
      "{} CRC-valid frames in {:.1f} s ({:.2f}/s), {:.0f}% of {} bytes explained cleanly; "
      "{} parity, {} framing errors, {} breaks",
      e.frames, static_cast<double>(e.listened) / 1e9, e.frames_per_second(),
      100.0 * e.clean_share(), e.bytes, e.parity_errors, e.framing_errors, e.breaks);
}

void diagnose(const std::vector<SettingEvidence>& table, ProbeVerdict& v) {
  // Frames whose bytes all carry a parity flag: the bytes are right, the parity is not.
  // Beside a winner that reads them clean it is what a device set that way would see.
  const SettingEvidence* clean = v.winner ? &table[*v.winner] : nullptr;
  if (clean != nullptr && clean->flagged_frame_bytes != 0) clean = nullptr;
  for (const auto& e : table) {
    // A flagged 00 byte reads as a break (FF 00 00): count those too.
    if (e.frames == 0 || e.line.parity == Parity::kNone ||
        share(e.parity_errors + e.breaks, e.bytes) < 0.9) {
      continue;
    }
    const std::string seen =
        fmt::format("parity errors on every byte at {} ({} of {}), yet {} CRC-valid frames",
                    e.line.describe(), e.parity_errors + e.breaks, e.bytes, e.frames);
    if (clean != nullptr && clean->line.baud == e.line.baud) {
      v.diagnoses.push_back(fmt::format(
          "{}: a device set to {} on this {} bus would reject every frame as a parity error", seen,
          e.line.describe(), clean->line.describe()));
    } else {
      v.diagnoses.push_back(
          fmt::format("{}: the parity is wrong, try {}", seen,
                      e.line.parity == Parity::kEven ? "odd or none" : "even or none"));
    }
  }
  const bool any_frames =
      std::any_of(table.begin(), table.end(), [](const auto& e) { return e.frames > 0; });
  // A swapped pair idles low: every burst ends in an error, at every rate (see
  // SettingEvidence::bursts); straight lines at wrong settings end about half of them so,
  // and many settings most of them clean. Reads that come late split a burst where there
  // was no silence, and the piece before such a split ends clean: on a loaded machine a
  // swapped pair's settings show up to three such ends in eight. So a setting reads the
  // bursts clean only when most of them end clean, and one setting in ten may still do so:
  // one whose port delivered no error marks while it listened (a driver that drops them,
  // or something else on the port that took PARMRK off).
  std::uint64_t bursts = 0;
  std::uint64_t flagged = 0;
  std::size_t settings_heard = 0;
  std::size_t settings_mostly_flagged = 0;
  for (const auto& e : table) {
    if (e.bursts < 3) continue;
    ++settings_heard;
    bursts += e.bursts;
    flagged += e.bursts_ending_flagged;
    if (2 * e.bursts_ending_flagged >= e.bursts) ++settings_mostly_flagged;
  }
  const std::size_t settings_read_clean = settings_heard - settings_mostly_flagged;
  if (!any_frames && settings_heard > 0 && settings_read_clean <= settings_heard / 10 &&
      share(flagged, bursts) >= 0.8) {
    v.inverted = true;
    v.diagnoses.push_back(fmt::format(
        "inverted line: swap A and B ({} of {} bursts end in a framing error or break; {} "
        "of {} settings end most bursts so, as a pair that idles low gives; no "
        "setting gives a CRC-valid frame)",
        flagged, bursts, settings_mostly_flagged, settings_heard));
  }
  if (v.winner) {
    const auto& w = table[*v.winner];
    // Lone bytes between frames, about one per turnaround: the line floats when released.
    const bool lone = w.lone_bytes >= 3 && 4 * w.lone_bytes >= w.frames;
    if (lone) {
      v.diagnoses.push_back(fmt::format(
          "bias: {} lone bytes between {} frames at {} ({} of them 00 or FF), as a line "
          "without fail-safe bias gives at turnarounds: check the bias resistors or the "
          "adapter's bias setting",
          w.lone_bytes, w.frames, w.line.describe(), w.lone_idle_bytes));
    }
    const std::uint64_t unexplained =
        w.line_errors() - std::min(w.line_errors(), lone ? w.lone_bytes : 0);
    if (share(unexplained, w.bytes) >= 0.05) {
      std::vector<std::string> others;
      for (const auto& e : table) {
        if (e.line.baud != w.line.baud && e.frames > 0) others.push_back(e.line.describe());
      }
      v.diagnoses.push_back(fmt::format(
          "{:.0f}% line errors even at {}{}: the device's rate may be off the standard one, "
          "or the line is noisy",
          100.0 * share(unexplained, w.bytes), w.line.describe(),
          others.empty() ? std::string()
                         : fmt::format(" (CRC-valid frames also at {})", fmt::join(others, ", "))));
    }
  } else if (!any_frames && !v.quiet && !v.inverted) {
    v.diagnoses.push_back(
        "bytes were heard but no setting gives CRC-valid frames: a rate outside the "
        "candidates, or a line too noisy to decode");
  } else if (!v.winner && any_frames) {
    for (const auto& e : table) {
      if (e.frames > 0 && e.clean_share() < kMinCleanShare) {
        v.diagnoses.push_back(
            fmt::format("CRC-valid frames only at {}, with most bytes unexplained: a neighbouring "
                        "rate, or a device whose clock is off",
                        e.line.describe()));
        break;
      }
    }
  }
}

}  // namespace

ProbeVerdict judge_probe(const std::vector<SettingEvidence>& table, bool quiet) {
  ProbeVerdict v;
  v.quiet = quiet;
  for (std::size_t i = 0; i < table.size(); ++i) v.ranking.push_back(i);
  std::stable_sort(v.ranking.begin(), v.ranking.end(), [&](std::size_t a, std::size_t b) {
    const auto& x = table[a];
    const auto& y = table[b];
    if (x.score() != y.score()) return x.score() > y.score();
    if (x.line_errors() != y.line_errors()) return x.line_errors() < y.line_errors();
    return x.bytes > y.bytes;
  });
  if (!v.ranking.empty()) {
    const std::size_t best = v.ranking.front();
    if (table[best].frames >= kMinFrames && table[best].clean_share() >= kMinCleanShare) {
      std::vector<std::size_t> group = {best};
      for (const auto i : v.ranking) {
        if (i != best && reads_alike(table[i], table[best])) group.push_back(i);
      }
      // Among settings read alike, the Modbus rule chooses; the winner heads the ranking.
      const auto chosen = *std::min_element(group.begin(), group.end(), [&](auto a, auto b) {
        return modbus_rule_rank(table[a].line) < modbus_rule_rank(table[b].line);
      });
      v.winner = chosen;
      for (const auto i : group) {
        if (i != chosen) v.alike.push_back(i);
      }
      v.ranking.erase(std::find(v.ranking.begin(), v.ranking.end(), chosen));
      v.ranking.insert(v.ranking.begin(), chosen);
    }
  }
  diagnose(table, v);
  return v;
}

std::string probe_text(const std::vector<SettingEvidence>& table, const ProbeVerdict& verdict,
                       std::size_t rows) {
  fmt::memory_buffer out;
  auto put = [&out](const std::string& s) { fmt::format_to(std::back_inserter(out), "{}", s); };
  put(fmt::format("{:<12} {:>6} {:>7} {:>8} {:>6} {:>6} {:>6} {:>6} {:>6}\n", "setting", "score",
                  "frames", "frames/s", "clean", "bytes", "parity", "frame", "break"));
  std::size_t shown = 0;
  for (const auto i : verdict.ranking) {
    if (shown++ >= rows) break;
    const auto& e = table[i];
    put(fmt::format("{:<12} {:>6.2f} {:>7} {:>8.2f} {:>5.0f}% {:>6} {:>6} {:>6} {:>6}\n",
                    e.line.describe(), e.score(), e.frames, e.frames_per_second(),
                    100.0 * e.clean_share(), e.bytes, e.parity_errors, e.framing_errors, e.breaks));
  }
  if (verdict.ranking.size() > rows) {
    put(fmt::format("({} more settings)\n", verdict.ranking.size() - rows));
  }
  if (verdict.winner) {
    const auto& w = table[*verdict.winner];
    put(fmt::format("winner: {}: {}\n", w.line.describe(), evidence_line(w)));
    if (!verdict.alike.empty()) {
      std::vector<std::string> names;
      for (const auto i : verdict.alike) names.push_back(table[i].line.describe());
      put(fmt::format(
          "  {} read alike here, cleanly (a UART checks one stop bit, and a port without "
          "parity checking cannot see parity): chosen by the Modbus rule, even parity, else "
          "2 stop bits\n",
          fmt::join(names, ", ")));
    }
  } else if (verdict.quiet) {
    put("no winner: the bus stayed quiet (not a byte at any setting)\n");
  } else {
    put("no winner: no setting gives enough CRC-valid frames\n");
  }
  for (const auto& d : verdict.diagnoses) put(fmt::format("diagnosis: {}\n", d));
  return fmt::to_string(out);
}

std::string probe_json(const std::vector<SettingEvidence>& table, const ProbeVerdict& verdict) {
  fmt::memory_buffer out;
  JsonWriter j(out);
  auto setting = [&](const SettingEvidence& e) {
    j.begin_object();
    j.field("setting", e.line.describe());
    j.field("baud", static_cast<std::uint64_t>(e.line.baud));
    const char parity[1] = {parity_letter(e.line.parity)};
    j.field("parity", std::string_view(parity, 1));
    j.field("stop_bits", static_cast<unsigned>(e.line.stop_bits));
    j.key("seconds");
    j.value_fixed(static_cast<double>(e.listened) / 1e9, 3);
    j.field("bytes", e.bytes);
    j.field("frames", e.frames);
    j.key("frames_per_second");
    j.value_fixed(e.frames_per_second(), 3);
    j.key("clean_share");
    j.value_fixed(e.clean_share(), 3);
    j.key("score");
    j.value_fixed(e.score(), 3);
    j.field("parity_errors", e.parity_errors);
    j.field("framing_errors", e.framing_errors);
    j.field("breaks", e.breaks);
    j.field("noise_bytes", e.noise_bytes());
    j.field("lone_bytes", e.lone_bytes);
    j.field("bursts", e.bursts);
    j.field("bursts_ending_flagged", e.bursts_ending_flagged);
    j.end_object();
  };
  j.begin_object();
  j.key("winner");
  if (verdict.winner) {
    setting(table[*verdict.winner]);
  } else {
    j.null();
  }
  j.key("alike");
  j.begin_array();
  for (const auto i : verdict.alike) j.value(table[i].line.describe());
  j.end_array();
  j.field("inverted", verdict.inverted);
  j.field("quiet", verdict.quiet);
  j.key("diagnoses");
  j.begin_array();
  for (const auto& d : verdict.diagnoses) j.value(d);
  j.end_array();
  j.key("settings");
  j.begin_array();
  for (const auto i : verdict.ranking) setting(table[i]);
  j.end_array();
  j.end_object();
  out.push_back('\n');
  return fmt::to_string(out);
}

}  // namespace rtu
