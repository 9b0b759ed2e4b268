#pragma once
// Judging what `rtuscope probe` heard: the ranking of the settings, the winner and the
// settings a UART cannot tell from it, and diagnoses of the line where the evidence
// allows one. Pure: the table in, the verdict and its text/JSON out.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "framing/setting_evidence.hpp"

namespace rtu {

struct ProbeVerdict {
  std::vector<std::size_t> ranking;   // indices into the table, best first
  std::optional<std::size_t> winner;  // nullopt: nothing fits
  // Settings at the winner's baud that read the traffic as cleanly (no error tells them
  // apart): the winner was chosen among them by the Modbus rule (even parity, else 2 stop
  // bits).
  std::vector<std::size_t> alike;
  std::vector<std::string> diagnoses;  // one line each, with its evidence
  bool inverted = false;               // the pattern of a swapped A/B pair
  bool quiet = false;
};

ProbeVerdict judge_probe(const std::vector<SettingEvidence>& table, bool quiet);

// The ranked table (at most `rows` rows), the winner with its evidence, the diagnoses.
std::string probe_text(const std::vector<SettingEvidence>& table, const ProbeVerdict& verdict,
                       std::size_t rows);
// {"winner": {...}|null, "alike": [...], "inverted": bool, "quiet": bool,
//  "diagnoses": [...], "settings": [{"setting": "9600 8E1", "baud", "parity", "stop_bits",
//  "seconds", "bytes", "frames", "frames_per_second", "clean_share", "score",
//  "parity_errors", "framing_errors", "breaks", "noise_bytes", "lone_bytes"}, ...]}
//  (ranked)
std::string probe_json(const std::vector<SettingEvidence>& table, const ProbeVerdict& verdict);

}  // namespace rtu
