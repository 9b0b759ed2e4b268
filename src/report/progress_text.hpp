#pragma once
// The words of a progress line (app/progress_line.hpp draws it on a terminal): how far a
// pass over an input has got, how fast it goes and when it should end. Only text here, so
// the numbers can be checked without a terminal or a clock.
#include <cstdint>
#include <string>
#include <string_view>

namespace rtu {

struct ProgressFigures {
  std::string_view label;     // what the pass does, e.g. "decoding 2/2"
  std::uint64_t bytes = 0;    // input bytes consumed so far
  std::uint64_t size = 0;     // input bytes in all (> 0)
  std::uint64_t records = 0;  // capture records read so far
  double seconds = 0;         // since the pass started
};

// Percent done, rounded down and never above 100 (a file may grow while it is read).
int progress_percent(std::uint64_t bytes, std::uint64_t size);

// "decoding 2/2  43%  12.5 MB/s  210k rec/s  ETA 0:12"; rates and ETA read "--" until they
// can be told (too early, nothing read yet).
std::string progress_text(const ProgressFigures& figures);

}  // namespace rtu
