#include "pipeline/replay.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <mutex>
#include <optional>
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
#include "pairing/transaction_tracker.hpp"
#include "pipeline/capture_feed.hpp"
#include "pipeline/first_look_gate.hpp"
#include "pipeline/framing_ahead.hpp"
#include "pipeline/line_inference.hpp"
#include "pipeline/line_warnings.hpp"

namespace rtu {
namespace {

// Pass 1: what the capture holds and how its reads are timed.
class Survey final : public CaptureConsumer {
 public:
  void on_chunk(const Chunk& chunk) override { add(chunk); }
  void on_byte_reads(const ByteReads& reads) override {
    chunks += reads.size();
    estimator.add(reads);
    line_check.add(reads);
  }
  void on_frame(std::span<const std::uint8_t> /*adu*/, Nanos /*t_start*/,
                std::uint64_t /*origin*/) override {
    ++records;
  }
  void on_noise(std::span<const std::uint8_t> /*bytes*/, Nanos /*t_start*/,
                std::uint64_t /*origin*/) override {
    ++records;
  }
  void on_end(Nanos /*t*/) override {}
  void add(const Chunk& chunk) {
    ++chunks;
    estimator.add(chunk);
    line_check.add(chunk);
  }
  [[nodiscard]] bool saw_bytes() const { return chunks > 0 || records > 0; }

  TimingEstimator estimator;
  LineCheck line_check;
  std::uint64_t chunks = 0;
  std::uint64_t records = 0;  // frame and noise records the file holds as such
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
  // `bytes_read`: how far the reader has got in its input, asked at each report.
  PassProgress(std::function<std::uint64_t()> bytes_read, std::uint64_t input_size,
               ReplayProgress::Pass pass, const ReplayOptions& options, bool only_pass = false)
      : bytes_read_(std::move(bytes_read)), options_(options) {
    progress_.pass = pass;
    progress_.only_pass = only_pass;
    progress_.input_size = input_size;
  }
  PassProgress(const CaptureReader& reader, ReplayProgress::Pass pass, const ReplayOptions& options,
               bool only_pass = false)
      : PassProgress([&reader] { return reader.bytes_read(); }, reader.input_size(), pass, options,
                     only_pass) {}
  // After each record read; only every kProgressEvery-th one costs more than an increment.
  void tick() {
    if (++progress_.records % kProgressEvery == 0) report(false);
  }
  // `records` read in all so far (delivered in batches).
  void reached(std::uint64_t records) {
    const bool due = records / kProgressEvery != progress_.records / kProgressEvery;
    progress_.records = records;
    if (due) report(false);
  }
  void done() { report(true); }

 private:
  void report(bool pass_done) {
    if (!options_.on_progress) return;
    progress_.bytes_read = bytes_read_();
    progress_.pass_done = pass_done;
    options_.on_progress(progress_);
  }
  std::function<std::uint64_t()> bytes_read_;
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
  info.has_bytes = survey.saw_bytes();
  info.per_byte_timing = info.has_bytes && result.use_chunks &&
                         (result.per_byte_exact || survey.estimator.mostly_single_bytes());
  for (auto& warning : reader.capture_warnings()) {
    // Not silent: what the file lacks shows as damaged frames, and the user must know why.
    if (options.show_warnings) print_warning_to_stderr(warning);
    info.warnings.push_back(std::move(warning));
  }
  // An empty file, or one of comments only, is a capture of nothing; more often it is the
  // wrong file, and a report of it must not read as a quiet bus.
  if (!info.has_bytes) {
    std::string warning = "the capture holds no bytes: nothing was decoded";
    if (options.show_warnings) print_warning_to_stderr(fmt::format("{}: {}", info.source, warning));
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

PipelineOptions pipeline_options(const CaptureSurvey& survey, const ReplayOptions& options) {
  const CaptureInfo& info = survey.info;
  PipelineOptions result;
  result.line = info.line;
  result.response_timeout = info.response_timeout;
  result.timing_resolution = info.timing_resolution;
  result.learn_resolution = !options.resolution;
  result.per_byte_timing = survey.per_byte_exact;
  return result;
}

// Pass 2 over `reader`, as `survey` says, into `sink`, all framing and pairing on this thread.
// `only_pass`: no survey pass came first. `resolution_at_end`: the framing's, once it finished
// (also when the reader threw).
void decode_pass(ReadAhead& reader, const CaptureSurvey& survey, const ReplayOptions& options,
                 RecordSink& sink, bool only_pass, Nanos& resolution_at_end) {
  const CaptureInfo& info = survey.info;
  // A first look needs the pairing apart from the framing, to stand between them.
  std::optional<TransactionTracker> tracker;
  std::optional<FirstLookGate> gate;
  std::optional<DecodePipeline> framing_and_pairing;
  if (options.first_look != nullptr) {
    tracker.emplace(TrackerConfig{info.response_timeout}, sink);
    gate.emplace(options.first_look, *tracker);
    framing_and_pairing.emplace(pipeline_options(survey, options),
                                static_cast<PairingInput&>(*gate));
  } else {
    framing_and_pairing.emplace(pipeline_options(survey, options), sink);
  }
  DecodePipeline& pipeline = *framing_and_pairing;
  pipeline.start(info);
  CaptureFeed feed(pipeline, survey.use_chunks, info.line.char_time(), options.on_chunk);
  PassProgress decode_progress(reader, ReplayProgress::Pass::kDecode, options, only_pass);
  try {
    while (reader.read(feed)) {
      decode_progress.tick();
    }
  } catch (...) {
    decode_progress.done();
    pipeline.finish();  // everything before the damage is still delivered
    resolution_at_end = pipeline.timing_resolution();
    throw;
  }
  decode_progress.done();
  pipeline.finish();
  resolution_at_end = pipeline.timing_resolution();
}

// Pass 2 to the end, as `survey` says, into `sink`: the reading and framing run on the
// second core (FramingAhead), the pairing and `sink` on this one. `only_pass`: no survey
// pass came first.
void decode_pass(FramingAhead& ahead, const ReplayOptions& options, RecordSink& sink,
                 bool only_pass) {
  TransactionTracker tracker(TrackerConfig{ahead.setup().info.response_timeout}, sink);
  FirstLookGate gate(options.first_look, tracker);
  PassProgress decode_progress([&ahead] { return ahead.bytes_read(); }, ahead.input_size(),
                               ReplayProgress::Pass::kDecode, options, only_pass);
  try {
    while (ahead.deliver(gate)) decode_progress.reached(ahead.items_read());
  } catch (...) {
    decode_progress.done();
    throw;
  }
  decode_progress.reached(ahead.items_read());
  decode_progress.done();
}

FramingAhead::Setup framing_setup(const CaptureSurvey& survey, const ReplayOptions& options) {
  FramingAhead::Setup setup;
  setup.pipeline = pipeline_options(survey, options);
  setup.info = survey.info;
  setup.use_chunks = survey.use_chunks;
  setup.on_chunk = options.on_chunk;
  return setup;
}

// The threads of a replay whose reader parses ahead: parsing (the lightest), framing, and
// pairing with all that follows it.
constexpr std::size_t kThreadsParsingAhead = 3;

// How one decoding pass is laid over the threads. Framing runs on the reading thread
// (FramingAhead) unless the caller keeps it on this one (ReplayOptions::frame_ahead, for
// reads of more than one byte). Where reads hold one byte each, parsing costs as much as
// framing: the reader then runs in a ReadAhead of its own inside the FramingAhead. Reads of
// several bytes parse on the framing thread: a third thread for them no longer pays, on two
// cores or one (reports, medians of 9 interleaved runs, 2,000,000 USB frames recorded as a
// live run records them: two cores 0.51 -> 0.45 s, one core 0.84 -> 0.81 s; the same frames
// from text hex and from `export --raw`'s pcapng unchanged on two cores, 0.90 -> 0.83 s from
// text hex on one). `alongside` (optional) sees every item on the parsing thread where there
// is one, else on the thread that frames them.
class DecodingRun {
 public:
  DecodingRun(std::unique_ptr<CaptureReader> reader, const CaptureSurvey& survey,
              const ReplayOptions& options, CaptureConsumer* alongside)
      : survey_(survey), options_(options) {
    // One-byte reads cost as much to parse as to frame: they are framed ahead on a thread of
    // their own, as the parsing is (below), whatever the caller's frame_ahead says.
    const bool frame_ahead = options.frame_ahead || survey.single_byte_reads;
    if (!frame_ahead) {
      parser_ =
          std::make_unique<ReadAhead>(std::move(reader), ReadAheadOptions{.alongside = alongside});
      return;
    }
    // One-byte reads reach the framing in runs only through the ReadAhead (500,000 per-byte
    // frames on one core: 0.37 s without it, 0.23 s with).
    if (survey.single_byte_reads) {
      // `alongside` goes with the parsing: framing is the busiest of the three threads
      // (callgrind, per-byte hex: parsing 204 M instructions, framing 395 M, pairing and
      // statistics 108 M), and the survey's 47 M moved off it took a tenth off the wall
      // time on two cores. Frame records that the framing leaves aside (it re-frames the raw
      // reads) are not handed over: in a native pcapng, one record of every frame.
      // The framing reads to the end: runs of one-byte reads go to it whole, a call each.
      parser_ = std::make_unique<ReadAhead>(
          std::move(reader), ReadAheadOptions{.alongside = alongside,
                                              .hand_over_records = !survey.use_chunks,
                                              .whole_byte_runs = true,
                                              .yields_among_threads = kThreadsParsingAhead});
      alongside = nullptr;
    }
    // The parser, when there is one, is owned by the framing from here on.
    parser_in_framing_ = parser_.get();
    framing_ = std::make_unique<FramingAhead>(parser_ ? std::move(parser_) : std::move(reader),
                                              framing_setup(survey, options), alongside);
  }

  // The whole pass into `sink`. `only_pass`: no survey pass came first.
  void decode(RecordSink& sink, bool only_pass) {
    if (framing_) {
      decode_pass(*framing_, options_, sink, only_pass);
    } else {
      decode_pass(*parser_, survey_, options_, sink, only_pass, resolution_at_end_);
    }
  }
  // The capture's info as the survey gave it, with the resolution the framing ended with
  // where the reads raised it; only once ended().
  [[nodiscard]] CaptureInfo info_at_end() const {
    CaptureInfo info = survey_.info;
    info.end_at_resolution(framing_ ? framing_->resolution_at_end() : resolution_at_end_);
    return info;
  }
  // Reading has ended (the pass ran to the end, or the reader threw).
  [[nodiscard]] bool ended() const { return framing_ ? framing_->ended() : parser_->ended(); }
  // The capture's reader, for what it learned; only once ended().
  const CaptureReader& source() {
    if (!framing_) return parser_->source();
    const CaptureReader& framed = framing_->source();  // joins the framing thread
    return parser_in_framing_ != nullptr ? parser_in_framing_->source() : framed;
  }

 private:
  const CaptureSurvey& survey_;
  const ReplayOptions& options_;
  std::unique_ptr<ReadAhead> parser_;       // when framing runs on this thread
  ReadAhead* parser_in_framing_ = nullptr;  // the one inside framing_, if any
  std::unique_ptr<FramingAhead> framing_;
  Nanos resolution_at_end_ = 0;  // when framing runs on this thread
};

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
  result.single_byte_reads = result.info.per_byte_timing;
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
  if (wants_inference(options.overrides, true)) return std::nullopt;
  if (!reader->declared_resolution() && !options.resolution) {
    try {
      while (start.chunks < kSampleReads && reader->read(start)) {
      }
    } catch (const InputError&) {
      return std::nullopt;
    }
    // Batched reads show their delivery period only over the whole capture.
    if (!start.estimator.mostly_single_bytes()) return std::nullopt;
  }
  CaptureSurvey result = decoding_settings(*reader, true, start.estimator, options);
  result.single_byte_reads = start.estimator.mostly_single_bytes();
  return result;
}

CaptureInfo decode_capture(const CaptureOpener& open, const CaptureSurvey& survey,
                           const ReplayOptions& options, RecordSink& sink, std::string* damage) {
  DecodingRun run(open([](std::string_view) {}), survey, options, nullptr);
  try {
    run.decode(sink, false);
  } catch (const InputError& error) {
    if (damage == nullptr) throw;
    *damage = error.what();
  }
  return run.info_at_end();
}

std::optional<CaptureInfo> decode_and_survey(const CaptureOpener& open, CaptureSurvey survey,
                                             const ReplayOptions& options, RecordSink& sink,
                                             std::string* damage) {
  HeldWarnings passing;
  Survey alongside;
  DecodingRun run(open(passing.sink()), survey, options, &alongside);
  // What survey_capture would have said, now that the whole capture was read.
  const auto surveyed = [&] {
    const CaptureReader& source = run.source();
    return decoding_settings(source, alongside.chunks > 0 || !source.holds_frames(),
                             alongside.estimator, options);
  };
  // Shown as survey_capture shows them: the passing warnings, then the whole capture's.
  const auto conclude = [&] {
    if (options.show_warnings) passing.show();
    add_whole_capture_findings(survey, run.source(), alongside, open, options);
  };
  try {
    run.decode(sink, true);
  } catch (const InputError& error) {
    // The input's damage (the reader's: it ended with it): what precedes it was surveyed.
    if (!run.ended()) throw;
    const bool same = same_decoding(surveyed(), survey);
    if (same) conclude();
    if (damage == nullptr) throw;
    if (!same) return std::nullopt;  // decoded again after survey_capture, up to the damage
    *damage = error.what();
    return run.info_at_end();
  } catch (...) {
    // Any other failure of the reading: what precedes it was surveyed all the same.
    if (run.ended() && same_decoding(surveyed(), survey)) conclude();
    throw;
  }
  if (!same_decoding(surveyed(), survey)) return std::nullopt;
  conclude();
  return run.info_at_end();
}

CaptureInfo replay_capture(const CaptureOpener& open, const ReplayOptions& options,
                           RecordSink& sink) {
  return decode_capture(open, survey_capture(open, options), options, sink);
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
