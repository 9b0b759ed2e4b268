#pragma once
// Reads a capture to its end or its error through a CaptureReader and checks, item by item,
// the contract of capture/capture_reader.hpp:
// - a chunk has at least one byte, line errors empty or one per byte, times in order where
//   the reader promises it, per-byte readers one byte with a measured start no later than
//   its end;
// - every span can be read in full (ASan checks the reads), origins lie inside the input;
// - the reader ends, or throws InputError naming a line or an offset of the input (as its
//   origins are), after
//   which a pcap reader delivers nothing more; warnings name the input too.
// Items are copied out, so a target may feed them on (spans die with the next read).
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "capture/capture_reader.hpp"
#include "capture/capture_warnings.hpp"

namespace rtu::fuzz {

struct CaptureRules {
  std::string_view target;  // for messages
  std::string_view text;    // the input, for line counts and its size
  bool per_byte_exact = false;
  bool times_in_order = false;    // the reader clamps backward times
  bool origins_are_lines = true;  // and errors name lines; else byte offsets
  // Read with read_many() and this room when not 0 (as a replay's reading thread reads),
  // else with read().
  std::size_t read_many_room = 0;
};

struct CaptureItem {
  enum class Kind : std::uint8_t { kChunk, kFrame, kNoise, kEnd };
  Kind kind = Kind::kChunk;
  std::vector<std::uint8_t> bytes;
  std::vector<std::uint8_t> errors;
  Nanos t = 0;  // chunk: t_end; frame, noise: t_start; end: when it ended
  Nanos t_first_start = kUnknownTime;
  std::uint64_t origin = 0;
  std::uint8_t port = 0;
};

struct CaptureRead {
  std::vector<CaptureItem> items;
  bool failed = false;  // ended with an InputError
};

using ReaderFactory = std::function<std::unique_ptr<CaptureReader>(WarningSink warnings)>;

// Opens the reader with `open` (which may itself throw InputError) and reads it all.
CaptureRead read_and_check(const ReaderFactory& open, const std::string& name,
                           const CaptureRules& rules);

}  // namespace rtu::fuzz
