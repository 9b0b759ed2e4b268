// The one two-pass replay driver (pipeline/replay.hpp): what it takes from any CaptureReader
// (chunks, frame and noise records, the capture's end, what the capture declares), checked
// with a scripted reader, and that real formats holding the same traffic decode alike.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bus_builder.hpp"
#include "capture/byte_output.hpp"
#include "capture/capture_reader.hpp"
#include "capture_test_files.hpp"
#include "core/crc16.hpp"
#include "core/input_error.hpp"
#include "core/issue.hpp"
#include "pipeline/replay.hpp"
#include "report/pcap_export.hpp"
#include "report/timing_note.hpp"
#include "report/traffic_stats.hpp"

namespace rtu {
namespace {

using test::CollectingSink;
using Bytes = std::vector<std::uint8_t>;

constexpr Nanos kMs = kNanosPerMilli;

Bytes with_crc(Bytes adu) {
  const std::uint16_t crc = crc16(adu);
  adu.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  adu.push_back(static_cast<std::uint8_t>(crc >> 8U));
  return adu;
}

const Bytes kRequest = with_crc({0x01, 0x03, 0x00, 0x00, 0x00, 0x01});
const Bytes kResponse = with_crc({0x01, 0x03, 0x02, 0x12, 0x34});

struct Item {
  enum class Kind : std::uint8_t { kChunk, kFrame, kNoise, kEnd, kDamage };
  Kind kind;
  Nanos t;
  Bytes bytes;
};

// What a test scripts the capture to hold and declare.
struct Script {
  std::vector<Item> items;
  bool holds_frames = true;
  Nanos precision = 1000;
  std::optional<Nanos> declared_resolution;
  std::optional<Nanos> declared_timeout;
  std::optional<LineSettings> declared_line;
  std::vector<std::string> warnings;
};

class ScriptedReader final : public CaptureReader {
 public:
  explicit ScriptedReader(const Script& script) : script_(script) {}
  bool read(CaptureConsumer& to) override {
    if (next_ == script_.items.size()) return false;
    const Item& item = script_.items[next_++];
    const auto origin = static_cast<std::uint64_t>(next_);
    switch (item.kind) {
      case Item::Kind::kChunk: {
        Chunk chunk;
        chunk.t_end = item.t;
        chunk.bytes = item.bytes;
        chunk.origin = origin;
        to.on_chunk(chunk);
        break;
      }
      case Item::Kind::kFrame: to.on_frame(item.bytes, item.t, origin); break;
      case Item::Kind::kNoise: to.on_noise(item.bytes, item.t, origin); break;
      case Item::Kind::kEnd: to.on_end(item.t); break;
      case Item::Kind::kDamage: throw InputError("scripted: offset 7: damaged");
    }
    return true;
  }
  [[nodiscard]] std::string name() const override { return "scripted"; }
  [[nodiscard]] Nanos timestamp_precision() const override { return script_.precision; }
  [[nodiscard]] std::optional<Nanos> declared_resolution() const override {
    return script_.declared_resolution;
  }
  [[nodiscard]] std::optional<Nanos> declared_timeout() const override {
    return script_.declared_timeout;
  }
  [[nodiscard]] std::optional<LineSettings> declared_settings() const override {
    return script_.declared_line;
  }
  [[nodiscard]] bool holds_frames() const override { return script_.holds_frames; }
  [[nodiscard]] std::vector<std::string> capture_warnings() const override {
    return script_.warnings;
  }

 private:
  const Script& script_;
  std::size_t next_ = 0;
};

struct Replayed {
  CaptureInfo info;
  CollectingSink sink;
  int opened = 0;
};

void replay(const Script& script, Replayed& out, ReplayOptions options = {}) {
  options.show_warnings = false;
  out.info = replay_capture(
      [&](WarningSink) {
        ++out.opened;
        return std::make_unique<ScriptedReader>(script);
      },
      options, out.sink);
}

std::vector<Bytes> bytes_of(const CollectingSink& sink) {
  std::vector<Bytes> out;
  for (const auto& record : sink.records) {
    out.emplace_back(record.bytes().begin(), record.bytes().end());
  }
  return out;
}

TEST(ReplayDriver, FrameRecordsAreDecodedAsTheyAreWhenThereAreNoRawReads) {
  Script script;
  script.items = {{Item::Kind::kFrame, 10 * kMs, kRequest},
                  {Item::Kind::kNoise, 30 * kMs, {0xFF}},
                  {Item::Kind::kFrame, 60 * kMs, kResponse}};
  Replayed r;
  replay(script, r);
  EXPECT_EQ(r.opened, 2);  // one reader per pass
  EXPECT_EQ(r.info.source, "scripted");
  EXPECT_FALSE(r.info.per_byte_timing);
  EXPECT_EQ(r.info.timing_resolution, script.precision);  // the records' own precision
  EXPECT_EQ(bytes_of(r.sink), (std::vector<Bytes>{kRequest, {0xFF}, kResponse}));
  ASSERT_EQ(r.sink.records.size(), 3U);
  EXPECT_EQ(r.sink.records[1].kind, RecordKind::kNoise);
  EXPECT_EQ(r.sink.requests_of_responses.size(), 1U);  // paired again
  EXPECT_TRUE(r.sink.finished);
}

TEST(ReplayDriver, RawReadsWinOverFrameRecords) {
  Script script;
  script.items = {{Item::Kind::kChunk, 10 * kMs, kRequest},
                  {Item::Kind::kFrame, 10 * kMs, with_crc({0x02, 0x01, 0x00, 0x00, 0x00, 0x08})},
                  {Item::Kind::kChunk, 60 * kMs, kResponse}};
  std::vector<std::size_t> seen_chunks;
  ReplayOptions options;
  options.on_chunk = [&](const Chunk& chunk) { seen_chunks.push_back(chunk.bytes.size()); };
  Replayed r;
  replay(script, r, options);
  EXPECT_EQ(bytes_of(r.sink), (std::vector<Bytes>{kRequest, kResponse}));
  EXPECT_EQ(seen_chunks, (std::vector<std::size_t>{kRequest.size(), kResponse.size()}));
}

TEST(ReplayDriver, DeclarationsOfTheCaptureAreUsedUnlessTheUserChose) {
  Script script;
  script.items = {{Item::Kind::kFrame, 10 * kMs, kRequest}};
  script.declared_resolution = 16 * kMs;
  script.declared_timeout = 300 * kMs;
  script.warnings = {"scripted: offset 9: record cut"};
  Replayed declared;
  replay(script, declared);
  EXPECT_EQ(declared.info.timing_resolution, 16 * kMs);
  EXPECT_EQ(declared.info.response_timeout, 300 * kMs);
  ASSERT_FALSE(declared.info.warnings.empty());
  EXPECT_EQ(declared.info.warnings.front(), "scripted: offset 9: record cut");

  ReplayOptions options;
  options.resolution = 2 * kMs;
  options.response_timeout = 500 * kMs;
  options.response_timeout_set = true;
  Replayed chosen;
  replay(script, chosen, options);
  EXPECT_EQ(chosen.info.timing_resolution, 2 * kMs);
  EXPECT_EQ(chosen.info.response_timeout, 500 * kMs);
}

TEST(ReplayDriver, TheCapturesEndDecidesAPendingRequest) {
  Script script;
  script.items = {{Item::Kind::kFrame, 10 * kMs, kRequest}};
  script.declared_timeout = 300 * kMs;
  Replayed without_end;
  replay(script, without_end);
  ASSERT_EQ(without_end.sink.records.size(), 1U);
  // The capture stops before the timeout ran out: no verdict.
  EXPECT_FALSE(without_end.sink.records[0].issues.has(IssueId::kTimeout));

  script.items.push_back({Item::Kind::kEnd, 5000 * kMs, {}});
  Replayed with_end;
  replay(script, with_end);
  ASSERT_EQ(with_end.sink.records.size(), 1U);
  EXPECT_TRUE(with_end.sink.records[0].issues.has(IssueId::kTimeout));
}

TEST(ReplayDriver, DamageIsReportedAfterEverythingBeforeIt) {
  Script script;
  script.items = {{Item::Kind::kFrame, 10 * kMs, kRequest},
                  {Item::Kind::kDamage, 0, {}},
                  {Item::Kind::kFrame, 60 * kMs, kResponse}};
  Replayed r;
  EXPECT_THROW(replay(script, r), InputError);
  EXPECT_EQ(bytes_of(r.sink), (std::vector<Bytes>{kRequest}));
  EXPECT_TRUE(r.sink.finished);
}

// Only a capture that declares its line and resolution, and starts with raw reads, is decoded
// without a survey pass; then decoding while surveying gives survey_capture's records and
// info, warnings and per-byte timing included.
TEST(ReplayDriver, ADeclaredSurveyNeedsDeclarationsAndRawReadsAndGivesTheSurveysAnswers) {
  Script script;
  script.declared_line = LineSettings{19200, Parity::kEven, 1};
  script.declared_resolution = 1 * kMs;
  script.warnings = {"scripted: offset 9: record cut"};
  for (int i = 0; i < 50; ++i) {
    script.items.push_back({Item::Kind::kChunk, (10 + 100 * i) * kMs, kRequest});
    script.items.push_back({Item::Kind::kChunk, (60 + 100 * i) * kMs, kResponse});
  }
  int opened = 0;
  const CaptureOpener open = [&](WarningSink) {
    ++opened;
    return std::make_unique<ScriptedReader>(script);
  };
  ReplayOptions options;
  options.show_warnings = false;
  const auto declared = declared_survey(open, options);
  ASSERT_TRUE(declared.has_value());
  EXPECT_EQ(declared->info.line.baud, 19200U);
  EXPECT_TRUE(declared->info.warnings.empty());
  CollectingSink alongside;
  const auto info = decode_and_survey(open, *declared, options, alongside);
  ASSERT_TRUE(info.has_value());
  Replayed surveyed;
  replay(script, surveyed);
  EXPECT_EQ(bytes_of(alongside), bytes_of(surveyed.sink));
  EXPECT_EQ(alongside.records.size(), 100U);
  EXPECT_EQ(info->warnings, surveyed.info.warnings);
  EXPECT_EQ(info->per_byte_timing, surveyed.info.per_byte_timing);
  EXPECT_EQ(info->timing_resolution, surveyed.info.timing_resolution);
  EXPECT_EQ(info->response_timeout, surveyed.info.response_timeout);

  Script frames_first = script;
  frames_first.items.insert(frames_first.items.begin(), 70,
                            {Item::Kind::kFrame, 1 * kMs, kRequest});
  Script undeclared_line = script;
  undeclared_line.declared_line.reset();
  Script undeclared_resolution = script;
  undeclared_resolution.declared_resolution.reset();
  for (const Script* refused : {&frames_first, &undeclared_line, &undeclared_resolution}) {
    const CaptureOpener open_refused = [&](WarningSink) {
      return std::make_unique<ScriptedReader>(*refused);
    };
    EXPECT_FALSE(declared_survey(open_refused, options).has_value());
  }
  // The user's resolution stands in for the capture's.
  options.resolution = 2 * kMs;
  const CaptureOpener open_undeclared = [&](WarningSink) {
    return std::make_unique<ScriptedReader>(undeclared_resolution);
  };
  EXPECT_TRUE(declared_survey(open_undeclared, options).has_value());
}

// A capture that declares a fine resolution, but whose reads arrive in batches with silences
// inside CRC-valid frames (an adapter's delivery), teaches the framing a coarser one. The
// decoding tells it at the end, alike with the survey first and alongside, and a report
// judges by it: t3.5 (2.0 ms at 19200 baud) is not observable through a 5.7 ms blur.
TEST(ReplayDriver, TheResolutionTheReadsShowedIsToldAtTheEndAndReportsJudgeByIt) {
  Script script;
  script.declared_line = LineSettings{19200, Parity::kEven, 1};
  script.declared_resolution = 1 * kMs;
  const auto split = [&](Nanos t, const Bytes& frame) {
    // The first half comes in one read, the rest in the next, 8 ms later.
    const auto half = static_cast<std::ptrdiff_t>(frame.size() / 2);
    script.items.push_back({Item::Kind::kChunk, t, Bytes(frame.begin(), frame.begin() + half)});
    script.items.push_back(
        {Item::Kind::kChunk, t + 8 * kMs, Bytes(frame.begin() + half, frame.end())});
  };
  for (int i = 0; i < 40; ++i) {
    split((10 + 100 * i) * kMs, kRequest);
    split((60 + 100 * i) * kMs, kResponse);
  }
  const CaptureOpener open = [&](WarningSink) { return std::make_unique<ScriptedReader>(script); };
  ReplayOptions options;
  options.show_warnings = false;
  TrafficStats surveyed_first(nullptr);
  const CaptureInfo info = replay_capture(open, options, surveyed_first);
  EXPECT_EQ(info.timing_resolution, 1 * kMs);  // what decoding started from, as declared
  ASSERT_NE(info.learned_resolution, kUnknownTime);
  // 8 ms between the reads, less the second half's own 4 or 3 characters (0.57 ms each).
  EXPECT_GT(info.learned_resolution, 5 * kMs);
  EXPECT_LT(info.learned_resolution, 8 * kMs);
  EXPECT_EQ(info.resolution_at_end(), info.learned_resolution);

  const auto declared = declared_survey(open, options);
  ASSERT_TRUE(declared.has_value());
  TrafficStats alongside(nullptr);
  const auto one_read = decode_and_survey(open, *declared, options, alongside);
  ASSERT_TRUE(one_read.has_value());
  EXPECT_EQ(one_read->learned_resolution, info.learned_resolution);

  // What a report says of it: before the end it knew only the declared resolution.
  EXPECT_TRUE(alongside.t35_observable());
  alongside.complete_capture(*one_read);
  EXPECT_FALSE(alongside.t35_observable());
  EXPECT_FALSE(alongside.t15_observable());
  EXPECT_EQ(resolution_text(*one_read),
            fmt::format("{:.3f} ms (learned from the reads: decoding started from 1.000 ms)",
                        to_millis(info.learned_resolution)));
  EXPECT_NE(timing_note(*one_read).find("not observable"), std::string::npos);

  // Reads that show no silence inside a frame teach nothing: nothing learned is told.
  Script whole_frames = script;
  whole_frames.items.clear();
  for (int i = 0; i < 40; ++i) {
    whole_frames.items.push_back({Item::Kind::kChunk, (10 + 100 * i) * kMs, kRequest});
    whole_frames.items.push_back({Item::Kind::kChunk, (60 + 100 * i) * kMs, kResponse});
  }
  CollectingSink sink;
  const CaptureInfo plain = replay_capture(
      [&](WarningSink) { return std::make_unique<ScriptedReader>(whole_frames); }, options, sink);
  EXPECT_EQ(plain.learned_resolution, kUnknownTime);
  EXPECT_EQ(plain.resolution_at_end(), 1 * kMs);
  EXPECT_EQ(resolution_text(plain), "1.000 ms");
}

std::vector<Bytes> decode_file(const std::string& path) {
  CollectingSink sink;
  ReplayOptions options;
  options.show_warnings = false;
  replay_capture(path, options, sink);
  return bytes_of(sink);
}

TEST(ReplayDriver, TextHexSaleaeAndPcapngOfTheSameTrafficDecodeAlike) {
  const std::string dir = std::string(RTUSCOPE_SOURCE_DIR) + "/captures/";
  const auto from_hex = decode_file(dir + "device_examples.hex");
  ASSERT_GT(from_hex.size(), 50U);
  EXPECT_EQ(decode_file(dir + "device_examples_saleae_legacy.csv"), from_hex);

  // Its export (frame records only) goes through the same driver.
  testing::TempDir temp;
  const std::string pcapng = (temp.path() / "examples.pcapng").string();
  {
    PcapExportSink exporter(std::make_unique<FileOutput>(pcapng), PcapExportOptions{});
    ReplayOptions options;
    options.show_warnings = false;
    replay_capture(dir + "device_examples.hex", options, exporter);
  }
  EXPECT_EQ(decode_file(pcapng), from_hex);
}

// Everything a sink can tell of a record, as a line (a copied record's request pointer is
// not followed: its sequence number is the response's own pairing).
std::string describe(const Record& r) {
  return fmt::format(
      "kind={} seq={} t={}..{} gap={} origin={} errors={} fit={} crc={} issues={:x} role={} "
      "txn={} latency={} {:02x}",
      static_cast<int>(r.kind), r.seq, r.t_start, r.t_end, r.gap_before, r.origin, r.line_errors,
      r.shape_fit, r.crc_ok, r.issues.bits(), static_cast<int>(r.role), r.txn, r.latency,
      fmt::join(r.bytes(), ""));
}

// The records of `path` with the decoding pass laid over the threads as `frame_ahead` says;
// with `alongside`, surveyed during the decoding where the capture allows.
std::vector<std::string> decoded_with(const std::string& path, bool frame_ahead, bool alongside) {
  CollectingSink sink;
  ReplayOptions options;
  options.show_warnings = false;
  options.frame_ahead = frame_ahead;
  const CaptureOpener open = capture_opener(CaptureFile{path});
  std::optional<CaptureSurvey> declared;
  if (alongside) declared = declared_survey(open, options);
  if (declared) {
    EXPECT_TRUE(decode_and_survey(open, *declared, options, sink).has_value()) << path;
  } else {
    replay_capture(open, options, sink);
  }
  std::vector<std::string> out;
  for (const Record& r : sink.records) out.push_back(describe(r));
  return out;
}

// Reading, parsing, framing and pairing may run on one, two or three threads (one-byte reads
// parse on a thread of their own): the records never depend on it. Every bundled text capture, and
// live-style recordings (raw reads beside frame records, settings declared: surveyed while
// decoding).
TEST(ReplayDriver, EveryThreadLayoutGivesTheSameRecords) {
  testing::TempDir temp;
  std::vector<std::string> paths = testing::bundled_text_captures();
  const std::string dir = std::string(RTUSCOPE_SOURCE_DIR) + "/captures/";
  std::size_t recordings = 0;
  for (const char* name :
       {"bus_9600_usb.hex", "bus_19200_faults_usb.hex", "bus_9600_perbyte.hex"}) {
    const std::string raw = (temp.path() / (std::string(name) + ".pcapng")).string();
    PcapExportSink exporter(std::make_unique<FileOutput>(raw),
                            PcapExportOptions{PcapExportFormat::kPcapng, true});
    ReplayOptions options;
    options.show_warnings = false;
    options.on_chunk = [&exporter](const Chunk& chunk) { exporter.on_chunk(chunk); };
    replay_capture(dir + name, options, exporter);
    paths.push_back(raw);
    ++recordings;
  }
  for (const auto& path : paths) {
    SCOPED_TRACE(path);
    const bool alongside = path.ends_with(".pcapng");
    const auto expected = decoded_with(path, false, alongside);
    EXPECT_GT(expected.size(), 2U);
    EXPECT_EQ(decoded_with(path, true, alongside), expected);
  }
  EXPECT_EQ(recordings, 3U);
  EXPECT_GE(paths.size(), 13U);
}

}  // namespace
}  // namespace rtu
