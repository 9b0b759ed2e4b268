#include "pipeline/replay.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <mutex>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "capture/capture_paths.hpp"
#include "capture/open_capture.hpp"
#include "capture/read_ahead.hpp"
#include "core/input_error.hpp"
#include "framing/framer.hpp"
#include "framing/timing_estimator.hpp"
#include "pipeline/line_inference.hpp"
#include "pipeline/line_warnings.hpp"

namespace rtu {
namespace {

// Pass 1: what the capture holds and how its reads are timed.
class Survey final : public CaptureConsumer {
 public:
  void on_chunk(const Chunk& chunk) override {
    ++chunks;
    estimator.add(chunk);
    line_check.add(chunk);
  }
  void on_frame(std::span<const std::uint8_t> /*adu*/, Nanos /*t_start*/,
                std::uint64_t /*origin*/) override {}
  void on_noise(std::span<const std::uint8_t> /*bytes*/, Nanos /*t_start*/,
                std::uint64_t /*origin*/) override {}
  void on_end(Nanos /*t*/) override {}

  TimingEstimator estimator;
  LineCheck line_check;
  std::uint64_t chunks = 0;
};

// Pass 2: everything into the pipeline, raw reads or frame records (see replay.hpp).
class Feed final : public CaptureConsumer {
 public:
  Feed(DecodePipeline& pipeline, const ReplayOptions& options, bool use_chunks, Nanos char_time)
      : pipeline_(pipeline), options_(options), use_chunks_(use_chunks), char_time_(char_time) {}

  void on_chunk(const Chunk& chunk) override {
    if (!use_chunks_) return;
    if (options_.on_chunk) options_.on_chunk(chunk);
    pipeline_.push(chunk);
  }
  void on_frame(std::span<const std::uint8_t> adu, Nanos t_start, std::uint64_t origin) override {
    if (use_chunks_) return;
    t_start = on_free_line(t_start);
    line_free_at_ = t_end(adu, t_start);
    pipeline_.push_frame(adu, t_start, line_free_at_, origin);
  }
  void on_noise(std::span<const std::uint8_t> bytes, Nanos t_start, std::uint64_t origin) override {
    if (use_chunks_) return;
    t_start = on_free_line(t_start);
    line_free_at_ = t_end(bytes, t_start);
    pipeline_.push_noise(bytes, t_start, line_free_at_, origin);
  }
  // A live recording ends where the live run stopped: what was pending then (a request
  // still waiting for its answer) is decided as live decided it.
  void on_end(Nanos t) override { pipeline_.idle(t); }

 private:
  [[nodiscard]] Nanos t_end(std::span<const std::uint8_t> bytes, Nanos t_start) const {
    return t_start + static_cast<Nanos>(bytes.size()) * char_time_;
  }
  // One line carries one record at a time: a record stamped before the previous one ended
  // (its time went backwards and was clamped by the reader, or another tool stamped it
  // late) starts when the line was free, so no latency or gap comes out negative.
  [[nodiscard]] Nanos on_free_line(Nanos t_start) const {
    return line_free_at_ != kUnknownTime && t_start < line_free_at_ ? line_free_at_ : t_start;
  }
  Nanos line_free_at_ = kUnknownTime;
  DecodePipeline& pipeline_;
  const ReplayOptions& options_;
  bool use_chunks_;
  Nanos char_time_;
};

// Frames the first reads of a capture hold at some settings: what confirms inferred ones.
class SampleFramer final : public CaptureConsumer, public RecordSink {
 public:
  explicit SampleFramer(const FramerConfig& config) : framer_(config, *this) {}

  void on_chunk(const Chunk& chunk) override {
    ++sample_.reads;
    framer_.push(chunk);
  }
  void on_frame(std::span<const std::uint8_t> /*adu*/, Nanos /*t_start*/,
                std::uint64_t /*origin*/) override {}
  void on_noise(std::span<const std::uint8_t> /*bytes*/, Nanos /*t_start*/,
                std::uint64_t /*origin*/) override {}
  void on_end(Nanos /*t*/) override {}
  void on_record(Record& record) override {
    if (record.kind != RecordKind::kFrame) return;
    ++sample_.frames;
    if (record.crc_ok) ++sample_.crc_ok;
  }

  FrameSample finish() {
    framer_.finish();
    return sample_;
  }
  [[nodiscard]] std::uint64_t reads() const { return sample_.reads; }

 private:
  Framer framer_;
  FrameSample sample_;
};

constexpr std::uint64_t kSampleReads = 20000;

FrameSample sample_frames(const CaptureOpener& open, const FramerConfig& config) {
  SampleFramer sample(config);
  try {
    auto reader = open([](std::string_view) {});
    while (sample.reads() < kSampleReads && reader->read(sample)) {
    }
  } catch (const InputError&) {
    // The decoding pass reports the damage; the sample ends at it.
  }
  return sample.finish();
}

// Tells ReplayOptions::on_progress how far one pass over a reader has got.
class PassProgress {
 public:
  PassProgress(const CaptureReader& reader, ReplayProgress::Pass pass, const ReplayOptions& options,
               bool only_pass = false)
      : reader_(reader), options_(options) {
    progress_.pass = pass;
    progress_.only_pass = only_pass;
  }
  // After each record read; only every kProgressEvery-th one costs more than an increment.
  void tick() {
    if (++progress_.records % kProgressEvery == 0) report(false);
  }
  void done() { report(true); }

 private:
  void report(bool pass_done) {
    if (!options_.on_progress) return;
    progress_.bytes_read = reader_.bytes_read();
    progress_.input_size = reader_.input_size();
    progress_.pass_done = pass_done;
    options_.on_progress(progress_);
  }
  const CaptureReader& reader_;
  const ReplayOptions& options_;
  ReplayProgress progress_;
};

}  // namespace

namespace {

// How the decoding pass reads the capture: from the reader's declarations, the options, and
// (where the capture declares no resolution) the survey's estimate. `use_chunks`: raw reads
// are re-framed, else frame records are decoded.
CaptureSurvey decoding_settings(const CaptureReader& reader, bool use_chunks,
                                const TimingEstimator& estimator, const ReplayOptions& options) {
  CaptureSurvey result;
  result.use_chunks = use_chunks;
  result.per_byte_exact = reader.timing_kind() == TimingKind::kPerByteExact;
  const Nanos precision = reader.timestamp_precision();
  CaptureInfo& info = result.info;
  info.source = reader.name();
  if (const auto declared = reader.declared_settings()) info.line = *declared;
  if (options.overrides.baud) info.line.baud = *options.overrides.baud;
  if (options.overrides.parity) info.line.parity = *options.overrides.parity;
  if (options.overrides.stop_bits) info.line.stop_bits = *options.overrides.stop_bits;
  if (use_chunks) {
    // A live recording declares the resolution its port achieved; replay uses the same,
    // so it frames exactly as the live run did.
    info.timing_resolution = reader.declared_resolution().value_or(estimator.resolution(precision));
  } else {
    // Frame records carry each frame's start; how well the original capture showed
    // silences is what its export declared, else the interface's resolution.
    info.timing_resolution = reader.declared_resolution().value_or(precision);
  }
  if (options.resolution) info.timing_resolution = *options.resolution;
  info.response_timeout = options.response_timeout;
  // A live recording says which response timeout decided its timeouts; unless the user
  // asks for another, replay uses the same.
  if (const auto timeout = reader.declared_timeout(); timeout && !options.response_timeout_set) {
    info.response_timeout = *timeout;
  }
  return result;
}

// What only the whole capture shows, added to `result` (and shown, when options say so):
// the reader's doubts, whether the reads held single bytes, settings inferred from the
// timing, and where the timing contradicts the settings.
void add_whole_capture_findings(CaptureSurvey& result, const CaptureReader& reader,
                                const Survey& survey, const CaptureOpener& open,
                                const ReplayOptions& options) {
  CaptureInfo& info = result.info;
  const Nanos precision = reader.timestamp_precision();
  const auto declared = reader.declared_settings();
  info.per_byte_timing =
      result.use_chunks && (result.per_byte_exact || survey.estimator.mostly_single_bytes());
  for (auto& warning : reader.capture_warnings()) {
    // Not silent: what the file lacks shows as damaged frames, and the user must know why.
    if (options.show_warnings) print_warning_to_stderr(warning);
    info.warnings.push_back(std::move(warning));
  }
  bool inferred = false;
  const std::size_t warnings_before = info.warnings.size();
  if (result.use_chunks && wants_inference(options.overrides, declared.has_value())) {
    const FrameSampler sampler = [&](const LineSettings& line) {
      return sample_frames(open, FramerConfig{line, info.timing_resolution, result.per_byte_exact,
                                              !options.resolution.has_value()});
    };
    inferred = infer_line_settings(info, survey.line_check, precision, options.overrides, sampler);
  }
  for (std::size_t i = warnings_before; options.show_warnings && i < info.warnings.size(); ++i) {
    print_warning_to_stderr(fmt::format("{}: {}", info.source, info.warnings[i]));
  }
  // Settings that were inferred, or that --baud auto said it could not infer, are not
  // "assumed" a second time.
  const bool explained = declared.has_value() || inferred || options.overrides.infer_baud;
  add_line_warnings(info, explained, options.overrides, survey.line_check, precision,
                    options.show_warnings);
}

// Pass 2 over `reader`, as `survey` says, into `sink`. `only_pass`: no survey pass came first.
void decode_from(ReadAhead& reader, const CaptureSurvey& survey, const ReplayOptions& options,
                 RecordSink& sink, bool only_pass = false) {
  const CaptureInfo& info = survey.info;
  PipelineOptions pipeline_options;
  pipeline_options.line = info.line;
  pipeline_options.response_timeout = info.response_timeout;
  pipeline_options.timing_resolution = info.timing_resolution;
  pipeline_options.learn_resolution = !options.resolution;
  pipeline_options.per_byte_timing = survey.per_byte_exact;
  DecodePipeline pipeline(pipeline_options, sink);
  pipeline.start(info);
  Feed feed(pipeline, options, survey.use_chunks, info.line.char_time());
  PassProgress decode_progress(reader, ReplayProgress::Pass::kDecode, options, only_pass);
  try {
    while (reader.read(feed)) {
      decode_progress.tick();
      if (options.enough && options.enough()) break;
    }
  } catch (...) {
    decode_progress.done();
    pipeline.finish();  // everything before the damage is still delivered
    throw;
  }
  decode_progress.done();
  pipeline.finish();
}

// True when `a` and `b` decode a capture alike.
bool same_decoding(const CaptureSurvey& a, const CaptureSurvey& b) {
  const CaptureInfo& x = a.info;
  const CaptureInfo& y = b.info;
  return a.use_chunks == b.use_chunks && a.per_byte_exact == b.per_byte_exact &&
         x.source == y.source && x.line == y.line && x.timing_resolution == y.timing_resolution &&
         x.response_timeout == y.response_timeout;
}

// A reader's passing warnings, kept (from the reading thread) to be shown in order later.
class HeldWarnings {
 public:
  WarningSink sink() {
    return [this](std::string_view message) {
      const std::lock_guard lock(mutex_);
      held_.emplace_back(message);
    };
  }
  void show() {
    const std::lock_guard lock(mutex_);
    for (const auto& message : held_) print_warning_to_stderr(message);
    held_.clear();
  }

 private:
  std::mutex mutex_;
  std::vector<std::string> held_;
};

// Items read before a declared survey settles how the capture is fed: the first raw read
// comes at once in a live recording.
constexpr std::uint64_t kPeekItems = 64;

}  // namespace

CaptureSurvey survey_capture(const CaptureOpener& open, const ReplayOptions& options) {
  // Reader warnings are shown once, here.
  auto first =
      options.show_warnings ? open(print_warning_to_stderr) : open([](std::string_view) {});
  Survey survey;
  PassProgress survey_progress(*first, ReplayProgress::Pass::kSurvey, options);
  try {
    while (first->read(survey)) survey_progress.tick();
  } catch (const InputError&) {
    // Damaged input: learn from what precedes the damage; pass 2 decodes up to it and
    // then reports the error.
  }
  survey_progress.done();
  // Frame records are decoded as they are only when there are no raw reads to re-frame.
  CaptureSurvey result = decoding_settings(*first, survey.chunks > 0 || !first->holds_frames(),
                                           survey.estimator, options);
  add_whole_capture_findings(result, *first, survey, open, options);
  return result;
}

std::optional<CaptureSurvey> declared_survey(const CaptureOpener& open,
                                             const ReplayOptions& options) {
  Survey start;
  auto reader = open([](std::string_view) {});
  try {
    for (std::uint64_t items = 0; items < kPeekItems && start.chunks == 0 && reader->read(start);
         ++items) {
    }
  } catch (const InputError&) {
    return std::nullopt;  // the full survey learns what precedes the damage
  }
  // Raw reads (or a format without frame records) are what survey_capture re-frames too;
  // frame records alone may be decoded as they are only if no read follows later.
  if (start.chunks == 0 && reader->holds_frames()) return std::nullopt;
  // Declarations are final once made (the first one wins); one made only later in the
  // capture (an undeclared timeout) is caught by decode_and_survey.
  if (!reader->declared_settings()) return std::nullopt;
  if (!reader->declared_resolution() && !options.resolution) return std::nullopt;
  if (wants_inference(options.overrides, true)) return std::nullopt;
  return decoding_settings(*reader, true, TimingEstimator{}, options);
}

void decode_capture(const CaptureOpener& open, const CaptureSurvey& survey,
                    const ReplayOptions& options, RecordSink& sink) {
  // The reader parses on the second core while this one decodes (same items, same order).
  ReadAhead reader(open([](std::string_view) {}));
  decode_from(reader, survey, options, sink);
}

std::optional<CaptureInfo> decode_and_survey(const CaptureOpener& open, CaptureSurvey survey,
                                             const ReplayOptions& options, RecordSink& sink) {
  HeldWarnings passing;
  Survey alongside;
  ReadAhead reader(open(passing.sink()), &alongside);
  ReplayOptions to_the_end = options;
  to_the_end.enough = nullptr;
  // What survey_capture would have said, now that the whole capture was read.
  const auto surveyed = [&] {
    const CaptureReader& source = reader.source();
    return decoding_settings(source, alongside.chunks > 0 || !source.holds_frames(),
                             alongside.estimator, options);
  };
  // Shown as survey_capture shows them: the passing warnings, then the whole capture's.
  const auto conclude = [&] {
    if (options.show_warnings) passing.show();
    add_whole_capture_findings(survey, reader.source(), alongside, open, options);
  };
  try {
    decode_from(reader, survey, to_the_end, sink, true);
  } catch (...) {
    // The input's damage: what precedes it was surveyed.
    if (reader.ended() && same_decoding(surveyed(), survey)) conclude();
    throw;
  }
  if (!same_decoding(surveyed(), survey)) return std::nullopt;
  conclude();
  return survey.info;
}

CaptureInfo replay_capture(const CaptureOpener& open, const ReplayOptions& options,
                           RecordSink& sink) {
  const CaptureSurvey survey = survey_capture(open, options);
  decode_capture(open, survey, options, sink);
  return survey.info;
}

CaptureOpener capture_opener(const CaptureFile& file) {
  return [file](WarningSink warnings) { return open_capture(file, std::move(warnings)); };
}

CaptureOpener capture_opener(const std::vector<CaptureFile>& files) {
  return [files](WarningSink warnings) { return open_captures(files, std::move(warnings)); };
}

CaptureInfo replay_capture(const CaptureFile& file, const ReplayOptions& options,
                           RecordSink& sink) {
  return replay_capture(capture_opener(file), options, sink);
}

CaptureInfo replay_capture(const std::vector<CaptureFile>& files, const ReplayOptions& options,
                           RecordSink& sink) {
  return replay_capture(capture_opener(files), options, sink);
}

CaptureInfo replay_capture(const std::vector<std::string>& paths, const ReplayOptions& options,
                           RecordSink& sink) {
  return replay_capture(std::vector<CaptureFile>(paths.begin(), paths.end()), options, sink);
}

}  // namespace rtu
