#pragma once
// Replays a capture file of any format (capture/capture_formats.hpp) through the decode
// pipeline in two passes over its CaptureReader: the first learns the timing resolution and
// the line settings the file declares (bounded memory), the second decodes. Options on the
// command line win over the file, which wins over the Modbus default 9600 8E1.
//
// A capture that holds known frames (pcap upper-PDU records) may hold raw reads too, as
// `rtuscope export --raw` writes them. Raw reads are the fuller evidence (silences, line
// errors), so when a file has any, they are re-framed and its frame records are left aside;
// otherwise the frame records are decoded as they are: CRC-checked, classified and paired
// again, each frame's end estimated as its start plus its length in character times. A frame
// record longer than 256 bytes is split into frames and noise (see DecodePipeline::push_frame).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "capture/capture_file.hpp"
#include "capture/capture_reader.hpp"
#include "capture/capture_warnings.hpp"
#include "framing/capture_info.hpp"
#include "framing/record.hpp"
#include "pipeline/decode_pipeline.hpp"
#include "pipeline/first_look.hpp"

namespace rtu {

// How far a replay has got, for a progress display (the driver itself never prints).
struct ReplayProgress {
  // Which read of the file: the first learns its timing, the second decodes.
  enum class Pass : std::uint8_t { kSurvey, kDecode };
  Pass pass = Pass::kSurvey;
  std::uint64_t bytes_read = 0;  // input bytes consumed in this pass
  std::uint64_t input_size = 0;  // bytes of input in all; 0 = unknown
  std::uint64_t records = 0;     // capture records (reads, frames) read in this pass
  bool pass_done = false;        // the last call of this pass (its reader ended or failed)
  bool only_pass = false;        // decoding is the only pass: the survey runs alongside it
};

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
  // Told every kProgressEvery records and at the end of each pass, when set.
  std::function<void(const ReplayProgress&)> on_progress;
  // Takes its look at the decoding pass's first records before the sink gets any (not owned;
  // optional): identification's sample, in the pass that decodes with what it found.
  FirstLook* first_look = nullptr;
  // Which core frames. Framing on the reading thread (FramingAhead) halves the decoding
  // core's work, which pays where the sink's work is at least the framing's (reports,
  // decode). An export's sink does little, so it frames on the decoding core and leaves the
  // reading core to the reader (ReadAhead). Where reads hold one byte each, parsing and
  // framing cost alike, and each gets a thread of its own whatever this says (a per-byte
  // export: about 0.8 -> 0.64 s wall for 1,000,000 frames on two cores). The records are
  // the same either way.
  bool frame_ahead = true;
};

// Records between two progress calls: a clock read per call stays off the hot path.
inline constexpr std::uint64_t kProgressEvery = 4096;

// Opens a fresh reader over the same capture for each pass, its passing warnings to `warnings`.
using CaptureOpener = std::function<std::unique_ptr<CaptureReader>(WarningSink warnings)>;

// What the first pass learned of a capture: how the second pass decodes it.
struct CaptureSurvey {
  CaptureInfo info;
  bool use_chunks = true;       // raw reads are re-framed (else frame records are decoded)
  bool per_byte_exact = false;  // a logic analyser's per-byte timing
  // The reads hold one byte each (in the survey, or in declared_survey's sample): parsing
  // them costs about as much as framing them, so each gets a thread of its own.
  bool single_byte_reads = false;
};

// Pass 1 alone: reads the whole capture once, shows its reader warnings (when asked) and
// says how to decode it. A capture damaged part-way is surveyed up to the damage.
CaptureSurvey survey_capture(const CaptureOpener& open, const ReplayOptions& options);

// Pass 2 alone: decodes the capture as `survey` says, into `sink`, and returns the survey's
// info with the resolution the reads showed while decoding (CaptureInfo::learned_resolution).
// Several decoding passes (identification, then the report) may share one survey. Damaged
// input throws InputError after every record before the damage was delivered; with `damage`
// given, its message goes there instead.
CaptureInfo decode_capture(const CaptureOpener& open, const CaptureSurvey& survey,
                           const ReplayOptions& options, RecordSink& sink,
                           std::string* damage = nullptr);

// Pass 1 without the pass, where the capture declares all that decoding needs (a live
// recording or `export --raw` declares line settings, resolution and response timeout) and
// its first items are raw reads: how to decode it, from a look at its start. A capture that
// declares its line settings but not its resolution qualifies when its first reads hold one
// byte each (a per-byte text capture): the resolution is then the timestamps' own
// precision, estimated from a sample as the survey estimates it from the whole capture.
// What only the whole capture shows (warnings, per_byte_timing, whether the estimate holds)
// is missing: decode_and_survey learns it while decoding. nullopt where the full
// survey_capture is needed.
std::optional<CaptureSurvey> declared_survey(const CaptureOpener& open,
                                             const ReplayOptions& options);

// Pass 2 with pass 1 alongside, on the reading thread: decodes as decode_capture does with
// `survey` from declared_survey, and returns the capture's info as survey_capture would have
// given it (with the resolution learned while decoding, as decode_capture gives it), its
// warnings shown at the end. A
// sink that needs the warnings before the records (a JSONL header) cannot use this.
// nullopt (nothing shown) when the whole capture says to decode otherwise than its start did
// (a response timeout declared only later): then what `sink` got is void, and the capture
// is to be decoded again after survey_capture.
// Damaged input throws InputError after every record before the damage was delivered; with
// `damage` given, its message goes there instead and the info of what precedes it is
// returned (a report of a capture cut short still covers all that was read).
std::optional<CaptureInfo> decode_and_survey(const CaptureOpener& open, CaptureSurvey survey,
                                             const ReplayOptions& options, RecordSink& sink,
                                             std::string* damage = nullptr);

// Decodes the capture once through `decode(survey, alongside)`: with declared_survey's survey
// and the survey alongside (decode_and_survey) where the capture allows it and the caller
// does (`alongside_allowed`); else, or when that decoding answers nullopt (decode it again),
// after survey_capture. `decode` answers nullopt only for a decoding alongside.
template <typename Result>
Result decode_surveyed(const CaptureOpener& open, const ReplayOptions& options,
                       bool alongside_allowed,
                       const std::function<std::optional<Result>(const CaptureSurvey& survey,
                                                                 bool alongside)>& decode) {
  if (alongside_allowed) {
    if (const auto declared = declared_survey(open, options)) {
      if (auto result = decode(*declared, true)) return std::move(*result);
    }
  }
  auto result = decode(survey_capture(open, options), false);
  if (!result) throw std::logic_error("a decoding after the survey pass gave no result");
  return std::move(*result);
}

// Opens the capture `file`, or the captures `files` as one capture in time order
// (capture/capture_paths.hpp), by the reader of their format. The opener keeps what the
// files refer to (a temporary copy of piped input) readable for as long as it lives.
CaptureOpener capture_opener(const CaptureFile& file);
CaptureOpener capture_opener(const std::vector<CaptureFile>& files);

// Decodes the capture `open` reads into `sink` and returns what was learned about it.
// Throws InputError for unusable input (after delivering every record before the damage).
CaptureInfo replay_capture(const CaptureOpener& open, const ReplayOptions& options,
                           RecordSink& sink);
// The same for the capture `file`, read by the reader of its format (open_capture).
CaptureInfo replay_capture(const CaptureFile& file, const ReplayOptions& options, RecordSink& sink);
// The same for several files read as one capture in time order (capture/capture_paths.hpp);
// one file reads exactly as above.
CaptureInfo replay_capture(const std::vector<CaptureFile>& files, const ReplayOptions& options,
                           RecordSink& sink);
CaptureInfo replay_capture(const std::vector<std::string>& paths, const ReplayOptions& options,
                           RecordSink& sink);

}  // namespace rtu
