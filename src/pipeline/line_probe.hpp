#pragma once
// `rtuscope probe`: listens on a port at candidate line settings in turn, never
// transmitting a byte, and collects what each setting shows (framing/setting_evidence.hpp).
// The only part of probing that touches the port and the clock; judging the evidence is
// report/probe_report.hpp.
#include <functional>
#include <string>
#include <vector>

#include "framing/setting_evidence.hpp"
#include "serial/line_settings.hpp"

namespace rtu {

struct ProbeOptions {
  std::string port;
  std::vector<LineSettings> candidates;  // in the order tried
  Nanos dwell = 2 * kNanosPerSecond;     // per setting
  Nanos max_time = 120 * kNanosPerSecond;
  // Stop at the first clear winner, once the other framings of its baud have been heard
  // too (they tell the parity apart).
  bool quick = false;
};

struct ProbeRun {
  std::vector<SettingEvidence> table;  // one entry per setting heard, in the order heard
  bool quiet = false;                  // not a byte at any setting, for as long as allowed
  Nanos elapsed = 0;
  std::vector<std::string> notes;  // what the port said when opened (said once)
};

// Every rate and framing probe knows, the common ones first when `quick`.
std::vector<LineSettings> probe_candidates(bool quick);

// Listens as `options` say. `on_setting` is called after each setting (progress);
// `on_quiet` once, when the first few settings heard nothing at all. Throws SerialOpenError when
// the port cannot be opened.
ProbeRun run_probe(const ProbeOptions& options,
                   const std::function<void(const SettingEvidence&)>& on_setting,
                   const std::function<void()>& on_quiet);

}  // namespace rtu
