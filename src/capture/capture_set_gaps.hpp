#pragma once
// Where a file seems to be missing from a capture set (capture/capture_set_reader.hpp), judged
// at each boundary between two files that follow each other in time:
//  * rotation numbering: both are named <stem>-<digits><ext> with the same stem and
//    extension (as `rtuscope live --rotate` names them) and the later file's number is more
//    than one above the earlier's. Files the recorder deleted with --keep are older than
//    every file kept, so they never leave such a jump inside a set;
//  * time: the silence from the earlier file's last record to the later file's first is
//    longer than kMissingSilenceFactor times the longest silence between records within
//    either file, and longer than kMissingSilenceFloor. A boundary of a rotation is an
//    ordinary silence of the traffic, so it is far shorter; the longest silence (rather
//    than a typical one) keeps bursty or slow polling from raising false alarms.
#include <cstdint>
#include <optional>
#include <string>

#include "core/time.hpp"

namespace rtu {

inline constexpr Nanos kMissingSilenceFactor = 10;
inline constexpr Nanos kMissingSilenceFloor = kNanosPerSecond;

// "site-0003.pcapng" → {"site", 3, ".pcapng"} (the folder is part of the stem).
struct RotationName {
  std::string stem;
  std::uint64_t number = 0;
  std::size_t digits = 0;
  std::string extension;
};
std::optional<RotationName> parse_rotation_name(const std::string& path);

struct SetBoundary {
  std::string before;  // the earlier file
  std::string after;   // the later file
  Nanos silence = 0;   // from the earlier file's last record to the later file's first
  // The longest silence between records within either file (0 when neither has two).
  Nanos longest_within = 0;
  // The earlier file ends with the recording's end (a recorder stopped, then started again).
  bool before_ended = false;
};

// The warning for one boundary, naming both files and every reason; nothing when no file
// seems to be missing there. Where the earlier file ends with the recording's end and the
// numbering goes on, nothing is missing: the warning says the recording stopped there and
// for how long the bus went unrecorded.
std::optional<std::string> missing_file_warning(const SetBoundary& boundary);

}  // namespace rtu
