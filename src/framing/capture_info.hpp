#pragma once
// Facts about a capture that every output states once, before the records.
#include <string>
#include <vector>

#include "core/time.hpp"
#include "serial/line_settings.hpp"

namespace rtu {

struct CaptureInfo {
  std::string source;  // file path or port name
  LineSettings line;
  // Smallest silence the timestamps can show. Gaps below it are not observable, so
  // t1.5/t3.5 issues are only reported where the silence in question is above it.
  Nanos timing_resolution = 0;
  // The resolution decoding ended with, where the reads raised it above timing_resolution
  // (an adapter's batching, seen in CRC-valid frames split across reads: Framer::learn_from);
  // kUnknownTime where they did not, and in outputs written before decoding ended.
  Nanos learned_resolution = kUnknownTime;
  bool per_byte_timing = false;  // every byte has its own timestamp
  // False for a capture file that holds no bytes at all: then no timing was observed.
  bool has_bytes = true;
  Nanos response_timeout = 1000 * kNanosPerMilli;
  // Doubts about the capture the user must see (line settings the data contradicts,
  // settings assumed because nothing declared them); also printed on stderr.
  std::vector<std::string> warnings;

  // The smallest silence the timestamps could show over the whole capture: what outputs
  // written at the end (reports) judge observability by.
  [[nodiscard]] Nanos resolution_at_end() const {
    return learned_resolution != kUnknownTime ? learned_resolution : timing_resolution;
  }
  // Notes the resolution decoding ended with (DecodePipeline::timing_resolution): learned
  // only where above the starting one.
  void end_at_resolution(Nanos at_end) {
    if (at_end > timing_resolution) learned_resolution = at_end;
  }
};

}  // namespace rtu
