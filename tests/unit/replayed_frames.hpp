#pragma once
// The frames `rtuscope decode` makes of a capture file, framed on the decoding thread or
// ahead of it (ReplayOptions::frame_ahead), for tests that compare the two paths; and the
// raw export of a capture, to decode again.
#include <memory>
#include <string>
#include <vector>

#include "bus_builder.hpp"
#include "capture/byte_output.hpp"
#include "pipeline/replay.hpp"
#include "report/pcap_export.hpp"

namespace rtu::test {

// Every record (frames, noise), in order.
inline std::vector<Record> replayed_records(const std::string& path, bool frame_ahead) {
  CollectingSink sink;
  ReplayOptions options;
  options.show_warnings = false;
  options.frame_ahead = frame_ahead;
  replay_capture(path, options, sink);
  return sink.records;
}

inline std::vector<Record> replayed_frames(const std::string& path, bool frame_ahead) {
  std::vector<Record> frames;
  for (const Record& r : replayed_records(path, frame_ahead)) {
    if (r.kind == RecordKind::kFrame) frames.push_back(r);
  }
  return frames;
}

// `rtuscope export --raw` of the capture at `path` into `out` (frames and raw reads).
inline void export_raw(const std::string& path, const std::string& out) {
  PcapExportOptions export_options;
  export_options.raw = true;
  PcapExportSink sink(std::make_unique<FileOutput>(out), export_options);
  ReplayOptions options;
  options.show_warnings = false;
  options.on_chunk = [&sink](const Chunk& chunk) { sink.on_chunk(chunk); };
  replay_capture(path, options, sink);
}

}  // namespace rtu::test
