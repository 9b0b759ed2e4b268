#include "pipeline/pcap_replay.hpp"

#include <optional>

#include "capture/capture_warnings.hpp"
#include "capture/pcap_import.hpp"
#include "core/input_error.hpp"
#include "framing/timing_estimator.hpp"
#include "pipeline/line_warnings.hpp"

namespace rtu {

CaptureInfo replay_pcap_capture(const std::string& path, const ReplayOptions& options,
                                RecordSink& sink) {
  // Pass 1: what the file holds, its timing resolution and declared line settings.
  TimingEstimator estimator;
  LineCheck line_check;
  std::uint64_t raw_chunks = 0;
  Nanos precision = 0;
  std::optional<LineSettings> declared;
  std::optional<Nanos> declared_resolution;
  std::optional<Nanos> declared_timeout;
  std::string cut_warning;
  {
    PcapImporter first(path);
    PcapItem item;
    try {
      while (first.next(item)) {
        if (precision == 0 || item.resolution < precision) precision = item.resolution;
        if (item.kind == PcapItem::Kind::kChunk) {
          ++raw_chunks;
          estimator.add(item.chunk);
          line_check.add(item.chunk);
        }
      }
    } catch (const InputError&) {
      // Learn from what precedes the damage; pass 2 decodes up to it, then reports it.
    }
    declared = first.declared_settings();
    declared_resolution = first.declared_resolution();
    declared_timeout = first.declared_timeout();
    cut_warning = cut_records_warning(path, first.cut_records());
  }
  const bool use_raw = raw_chunks > 0;

  CaptureInfo info;
  info.source = path;
  if (!cut_warning.empty()) {
    // Not silent: what the file lacks shows as damaged frames, and the user must know why.
    if (options.show_warnings) print_warning_to_stderr(cut_warning);
    info.warnings.push_back(cut_warning);
  }
  if (declared) info.line = *declared;
  if (options.overrides.baud) info.line.baud = *options.overrides.baud;
  if (options.overrides.parity) info.line.parity = *options.overrides.parity;
  if (options.overrides.stop_bits) info.line.stop_bits = *options.overrides.stop_bits;
  if (use_raw) {
    info.per_byte_timing = estimator.mostly_single_bytes();
    // A live recording declares the resolution its port achieved; replay uses the same,
    // so it frames exactly as the live run did.
    info.timing_resolution = declared_resolution.value_or(estimator.resolution(precision));
  } else {
    // Frame records carry each frame's start; how well the original capture showed
    // silences is what its export declared, else the interface's resolution.
    info.per_byte_timing = false;
    info.timing_resolution = declared_resolution.value_or(precision);
  }
  if (options.resolution) info.timing_resolution = *options.resolution;
  info.response_timeout = options.response_timeout;
  // A live recording says which response timeout decided its timeouts; unless the user
  // asks for another, replay uses the same.
  if (declared_timeout && !options.response_timeout_set) info.response_timeout = *declared_timeout;
  add_line_warnings(info, declared.has_value(), options.overrides, line_check, precision,
                    options.show_warnings);

  // Pass 2: decode.
  PipelineOptions pipeline_options;
  pipeline_options.line = info.line;
  pipeline_options.response_timeout = info.response_timeout;
  pipeline_options.timing_resolution = info.timing_resolution;
  pipeline_options.learn_resolution = !options.resolution;
  pipeline_options.per_byte_timing = false;
  DecodePipeline pipeline(pipeline_options, sink);
  pipeline.start(info);
  PcapImporter second(path);
  PcapItem item;
  const Nanos char_time = info.line.char_time();
  try {
    while (second.next(item)) {
      if (item.kind == PcapItem::Kind::kEnd) {
        // A live recording ends where the live run stopped: what was pending then (a
        // request still waiting for its answer) is decided as live decided it.
        pipeline.idle(item.t_start);
        continue;
      }
      if (item.kind == PcapItem::Kind::kChunk) {
        if (!use_raw) continue;
        if (options.on_chunk) options.on_chunk(item.chunk);
        pipeline.push(item.chunk);
        continue;
      }
      if (use_raw) continue;
      const Nanos t_end = item.t_start + static_cast<Nanos>(item.bytes.size()) * char_time;
      if (item.kind == PcapItem::Kind::kFrame) {
        pipeline.push_frame(item.bytes, item.t_start, t_end, item.offset);
      } else {
        pipeline.push_noise(item.bytes, item.t_start, t_end, item.offset);
      }
    }
  } catch (...) {
    pipeline.finish();  // everything before the damage is still delivered
    throw;
  }
  pipeline.finish();
  return info;
}

}  // namespace rtu
