#include "pipeline/replay.hpp"

#include "capture/open_capture.hpp"
#include "core/input_error.hpp"
#include "framing/timing_estimator.hpp"
#include "pipeline/line_warnings.hpp"
#include "pipeline/pcap_replay.hpp"

namespace rtu {

CaptureInfo replay_capture(const std::string& path, const ReplayOptions& options,
                           RecordSink& sink) {
  if (detect_capture_format(path) == CaptureFormat::kPcap) {
    return replay_pcap_capture(path, options, sink);
  }
  // Pass 1: timing resolution and declared settings. Reader warnings are shown once, here.
  TimingEstimator estimator;
  LineCheck line_check;
  auto first =
      options.show_warnings ? open_capture(path) : open_capture(path, [](std::string_view) {});
  Chunk chunk;
  try {
    while (first->next(chunk)) {
      estimator.add(chunk);
      line_check.add(chunk);
    }
  } catch (const InputError&) {
    // Damaged input: learn from what precedes the damage; pass 2 decodes up to it and
    // then reports the error.
  }

  CaptureInfo info;
  info.source = path;
  if (auto declared = first->declared_settings()) info.line = *declared;
  if (options.overrides.baud) info.line.baud = *options.overrides.baud;
  if (options.overrides.parity) info.line.parity = *options.overrides.parity;
  if (options.overrides.stop_bits) info.line.stop_bits = *options.overrides.stop_bits;
  const bool exact = first->timing_kind() == TimingKind::kPerByteExact;
  info.per_byte_timing = exact || estimator.mostly_single_bytes();
  info.timing_resolution =
      options.resolution ? *options.resolution : estimator.resolution(first->timestamp_precision());
  info.response_timeout = options.response_timeout;
  add_line_warnings(info, first->declared_settings().has_value(), options.overrides, line_check,
                    first->timestamp_precision(), options.show_warnings);
  first.reset();

  // Pass 2: decode.
  PipelineOptions pipeline_options;
  pipeline_options.line = info.line;
  pipeline_options.response_timeout = info.response_timeout;
  pipeline_options.timing_resolution = info.timing_resolution;
  pipeline_options.learn_resolution = !options.resolution;
  pipeline_options.per_byte_timing = exact;
  DecodePipeline pipeline(pipeline_options, sink);
  pipeline.start(info);
  auto second = open_capture(path, [](std::string_view) {});
  try {
    while (second->next(chunk)) {
      if (options.on_chunk) options.on_chunk(chunk);
      pipeline.push(chunk);
    }
  } catch (...) {
    pipeline.finish();  // everything before the damage is still delivered
    throw;
  }
  pipeline.finish();
  return info;
}

}  // namespace rtu
