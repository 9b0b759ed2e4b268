#pragma once
// Replays a capture file through the decode pipeline in two passes: the first learns the
// timing resolution and the line settings the file declares (bounded memory), the second
// decodes. Options on the command line win over the file, which wins over the Modbus
// default 9600 8E1.
#include <functional>
#include <optional>
#include <string>

#include "framing/capture_info.hpp"
#include "framing/record.hpp"
#include "pipeline/decode_pipeline.hpp"

namespace rtu {

struct ReplayOptions {
  LineOverrides overrides;
  Nanos response_timeout = 1000 * kNanosPerMilli;
  // True when the user chose response_timeout (command line, bus file): it then wins over
  // a timeout the capture file declares.
  bool response_timeout_set = false;
  std::optional<Nanos> resolution;  // overrides the estimate
  // Sees every chunk of the decoding pass just before the pipeline does (raw exports).
  std::function<void(const Chunk&)> on_chunk;
  // Reader warnings go to stderr; off for an extra pass over a file already read once.
  bool show_warnings = true;
};

// Decodes `path` into `sink` and returns what was learned about the capture.
// Throws InputError for unusable input (after delivering every record before the damage).
CaptureInfo replay_capture(const std::string& path, const ReplayOptions& options, RecordSink& sink);

}  // namespace rtu
