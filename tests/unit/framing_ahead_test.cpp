// FramingAhead tells the tracker exactly what a DecodePipeline's own tracker is told, so the
// records out of the tracker are identical to a single-threaded decoding: for every bundled
// capture, across batch boundaries, up to and including the reader's error, with raw reads
// seen at the same points between records. It can be dropped part-way, and a consumer
// alongside sees every item on the reading thread.
#include "pipeline/framing_ahead.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "capture/open_capture.hpp"
#include "capture/read_ahead.hpp"
#include "capture_test_files.hpp"
#include "core/input_error.hpp"
#include "core/thread_name.hpp"
#include "item_transcript.hpp"
#include "pairing/transaction_tracker.hpp"
#include "pipeline/capture_feed.hpp"
#include "record_transcript.hpp"

namespace rtu {
namespace {

// Writes every call it gets as one line of text: records with all the tracker gave them, and
// capture items as ItemTranscript writes them.
class Transcript final : public RecordSink, public testing::ItemTranscript {
 public:
  void on_capture(const CaptureInfo& info) override {
    lines.push_back(fmt::format("capture {} baud={}", info.source, info.line.baud));
  }
  void on_record(Record& r) override { lines.push_back(testing::describe_record(r)); }
  void on_finish() override { lines.emplace_back("finish"); }
};

FramingAhead::Setup setup_for(const CaptureReader& reader, Transcript* chunks) {
  FramingAhead::Setup setup;
  setup.info.source = reader.name();
  if (const auto line = reader.declared_settings()) setup.info.line = *line;
  setup.info.timing_resolution = 2 * kNanosPerMilli;
  setup.info.response_timeout = 50 * kNanosPerMilli;  // shorter than the long capture's polls
  setup.pipeline.line = setup.info.line;
  setup.pipeline.timing_resolution = setup.info.timing_resolution;
  setup.pipeline.response_timeout = setup.info.response_timeout;
  setup.use_chunks = !reader.holds_frames();
  if (chunks != nullptr) setup.on_chunk = [chunks](const Chunk& c) { chunks->on_chunk(c); };
  return setup;
}

// The single-threaded decoding: reader, pipeline and tracker on this thread.
std::vector<std::string> decoded_directly(const std::string& path, bool with_chunks) {
  auto reader = open_capture(path, [](std::string_view) {});
  Transcript out;
  const auto setup = setup_for(*reader, with_chunks ? &out : nullptr);
  DecodePipeline pipeline(setup.pipeline, out);
  pipeline.start(setup.info);
  CaptureFeed feed(pipeline, setup.use_chunks, setup.info.line.char_time(), setup.on_chunk);
  try {
    while (reader->read(feed)) {
    }
  } catch (const InputError& e) {
    pipeline.finish();
    out.lines.push_back(std::string("error: ") + e.what());
    return out.lines;
  }
  pipeline.finish();
  return out.lines;
}

// `parse_ahead`: the reader runs in a ReadAhead of its own that hands runs of one-byte reads
// over whole, as a replay of a per-byte capture does. `items`, if given, gets items_read().
std::vector<std::string> decoded_ahead(const std::string& path, bool with_chunks,
                                       bool parse_ahead = false, std::uint64_t* items = nullptr,
                                       CaptureConsumer* alongside = nullptr) {
  std::unique_ptr<CaptureReader> reader = open_capture(path, [](std::string_view) {});
  Transcript out;
  const auto setup = setup_for(*reader, with_chunks ? &out : nullptr);
  if (parse_ahead) {
    reader = std::make_unique<ReadAhead>(std::move(reader),
                                         ReadAheadOptions{.hand_over_records = !setup.use_chunks,
                                                          .whole_byte_runs = true,
                                                          .yields_among_threads = 3});
  }
  FramingAhead ahead(std::move(reader), setup, alongside);
  EXPECT_EQ(ahead.name(), path);
  TransactionTracker tracker(TrackerConfig{setup.info.response_timeout}, out);
  try {
    while (ahead.deliver(tracker)) {
    }
    if (ahead.deliver(tracker)) out.lines.emplace_back("deliver after the end returned true");
  } catch (const InputError& e) {
    out.lines.push_back(std::string("error: ") + e.what());
    if (ahead.deliver(tracker)) out.lines.emplace_back("deliver after the error returned true");
  }
  EXPECT_TRUE(ahead.ended());
  if (items != nullptr) *items = ahead.items_read();
  return out.lines;
}

void expect_same_records(const std::string& path) {
  SCOPED_TRACE(path);
  for (const bool with_chunks : {false, true}) {
    const auto expected = decoded_directly(path, with_chunks);
    EXPECT_EQ(decoded_ahead(path, with_chunks), expected);
    EXPECT_GT(expected.size(), 2U);
  }
}

// Polling at 9600 baud, read by read, several batches' worth; with a request that is never
// answered now and then (its timeout decided by a later read), and ending in a line that is
// not a capture line when `damaged`.
std::string write_long_capture(const testing::TempDir& dir, bool damaged) {
  std::string text = "# baud=9600 parity=E stop=1\n";
  const std::string request = "01 03 00 00 00 01 84 0A";
  const std::string response = "01 03 02 00 2A 39 9B";
  const std::size_t polls = 3 * FramingAhead::kBatchSteps + 17;
  for (std::size_t i = 0; i < polls; ++i) {
    const std::size_t ms = i * 100;
    text += fmt::format("{}.{:03d}000 {}\n", ms / 1000, ms % 1000, request);
    if (i % 7 != 3) text += fmt::format("{}.{:03d}000 {}\n", ms / 1000, ms % 1000 + 30, response);
  }
  if (damaged) text += "not a capture line\n";
  return dir.write(damaged ? "damaged.hex" : "long.hex", text);
}

// Polling at 9600 baud as a per-byte capture holds it, a line for each byte stamped when it
// ended: several of a ReadAhead's batches, whose runs of one-byte reads end at the batch ends.
std::string write_per_byte_capture(const testing::TempDir& dir, bool damaged) {
  std::string text = "# baud=9600 parity=E stop=1\n";
  const std::vector<std::uint8_t> request = {0x01, 0x03, 0x00, 0x00, 0x00, 0x01, 0x84, 0x0A};
  const std::vector<std::uint8_t> response = {0x01, 0x03, 0x02, 0x00, 0x2A, 0x39, 0x9B};
  const Nanos char_time = LineSettings{}.char_time();
  const std::size_t polls = 3 * ReadAhead::kBatchItems / 14 + 41;
  Nanos t = 0;
  const auto add = [&](const std::vector<std::uint8_t>& frame) {
    for (const std::uint8_t byte : frame) {
      t += char_time;
      text += fmt::format("{}.{:09d} {:02X}\n", t / kNanosPerSecond, t % kNanosPerSecond, byte);
    }
  };
  for (std::size_t i = 0; i < polls; ++i) {
    t = static_cast<Nanos>(i) * 100 * kNanosPerMilli;
    add(request);
    t += 5 * kNanosPerMilli;
    if (i % 7 != 3) add(response);
  }
  if (damaged) text += "not a capture line\n";
  return dir.write(damaged ? "per-byte-damaged.hex" : "per-byte.hex", text);
}

std::uint64_t reads_in(const std::string& path) {
  auto reader = open_capture(path, [](std::string_view) {});
  Transcript ignored;
  std::uint64_t reads = 0;
  try {
    while (reader->read(ignored)) ++reads;
  } catch (const InputError&) {
    // The reads before the damage are what counts.
  }
  return reads;
}

// Runs of one-byte reads handed over whole (one call for up to a batch of them) are framed
// as the reads one by one: the same records at the same points, the same raw reads where a
// callback sees them (it then gets them one at a time), and every read counted as an item.
TEST(FramingAhead, RunsOfOneByteReadsHandedOverWholeAreFramedAsTheReadsOneByOne) {
  const testing::TempDir dir;
  auto paths = testing::bundled_text_captures();
  paths.push_back(write_per_byte_capture(dir, false));
  paths.push_back(write_per_byte_capture(dir, true));
  for (const auto& path : paths) {
    SCOPED_TRACE(path);
    for (const bool with_chunks : {false, true}) {
      std::uint64_t items = 0;
      EXPECT_EQ(decoded_ahead(path, with_chunks, true, &items),
                decoded_directly(path, with_chunks));
      EXPECT_EQ(items, reads_in(path));
    }
  }
  const auto lines = decoded_directly(paths.back(), false);
  EXPECT_EQ(lines.back().rfind("error: ", 0), 0U) << lines.back();
  EXPECT_GT(reads_in(paths.back()), 2 * ReadAhead::kBatchItems);
}

TEST(FramingAhead, TellsWhatTheTrackerIsToldInOneThreadForEveryBundledCapture) {
  const auto paths = testing::bundled_text_captures();
  for (const auto& path : paths) expect_same_records(path);
  EXPECT_GE(paths.size(), 10U);
}

TEST(FramingAhead, CrossesBatchesAndThrowsTheReadersErrorAfterEverythingBeforeIt) {
  const testing::TempDir dir;
  for (const bool damaged : {false, true}) {
    const std::string path = write_long_capture(dir, damaged);
    expect_same_records(path);
    const auto lines = decoded_ahead(path, false);
    EXPECT_EQ(lines.back().rfind("error: ", 0) == 0, damaged) << lines.back();
    EXPECT_EQ(lines[lines.size() - (damaged ? 2 : 1)], "finish");
  }
}

TEST(FramingAhead, CanBeDroppedBeforeTheEnd) {
  const testing::TempDir dir;
  const std::string path = write_long_capture(dir, false);
  for (const int batches : {0, 1, 2}) {
    auto reader = open_capture(path, [](std::string_view) {});
    const auto setup = setup_for(*reader, nullptr);
    FramingAhead ahead(std::move(reader), setup);
    Transcript out;
    TransactionTracker tracker(TrackerConfig{setup.info.response_timeout}, out);
    for (int i = 0; i < batches; ++i) ASSERT_TRUE(ahead.deliver(tracker));
    EXPECT_EQ(out.lines.empty(), batches == 0);
    EXPECT_FALSE(ahead.ended());
  }  // the destructor stops the reading thread, which may be waiting for a free batch
}

// A consumer alongside sees every item, as a direct read gives them (on the reading thread),
// and the reader answers for the whole capture once reading ended: never before.
TEST(FramingAhead, AConsumerAlongsideSeesEveryItemAndTheReaderIsAskedOnlyAtTheEnd) {
  const testing::TempDir dir;
  for (const bool damaged : {false, true}) {
    const std::string path = write_long_capture(dir, damaged);
    Transcript expected;
    auto direct = open_capture(path, [](std::string_view) {});
    try {
      while (direct->read(expected)) {
      }
    } catch (const InputError&) {
      // The consumer alongside does not see read() throw: only the items.
    }
    auto reader = open_capture(path, [](std::string_view) {});
    const auto setup = setup_for(*reader, nullptr);
    Transcript alongside;
    FramingAhead ahead(std::move(reader), setup, &alongside);
    Transcript out;
    TransactionTracker tracker(TrackerConfig{setup.info.response_timeout}, out);
    ASSERT_TRUE(ahead.deliver(tracker));
    EXPECT_FALSE(ahead.ended());
    EXPECT_THROW((void)ahead.source(), std::logic_error);
    try {
      while (ahead.deliver(tracker)) {
      }
      EXPECT_FALSE(damaged);
    } catch (const InputError&) {
      EXPECT_TRUE(damaged);
    }
    EXPECT_TRUE(ahead.ended());
    EXPECT_EQ(alongside.lines, expected.lines);
    const CaptureReader& source = ahead.source();
    ASSERT_TRUE(source.declared_settings().has_value());
    EXPECT_EQ(source.declared_settings()->baud, 9600U);
    EXPECT_EQ(source.bytes_read(), ahead.bytes_read());
    EXPECT_GT(ahead.items_read(), 3 * FramingAhead::kBatchSteps);
  }
}

// Notes the name of the thread that delivers it the capture's first item.
class ThreadNameNotingConsumer final : public CaptureConsumer {
 public:
  void on_chunk(const Chunk& /*chunk*/) override { note(); }
  void on_frame(std::span<const std::uint8_t> /*adu*/, Nanos /*t_start*/,
                std::uint64_t /*origin*/) override {
    note();
  }
  void on_noise(std::span<const std::uint8_t> /*bytes*/, Nanos /*t_start*/,
                std::uint64_t /*origin*/) override {
    note();
  }
  void on_end(Nanos /*t*/) override { note(); }

  std::string name;

 private:
  void note() {
    if (name.empty()) name = this_thread_name();
  }
};

// The framing runs on a thread named for it (ps -L, top -H, perf show which stage is busy).
TEST(FramingAhead, FramesOnAThreadNamedForFraming) {
  const testing::TempDir dir;
  ThreadNameNotingConsumer alongside;
  decoded_ahead(write_long_capture(dir, false), false, false, nullptr, &alongside);
  EXPECT_EQ(alongside.name, "rtu-framing");
}

}  // namespace
}  // namespace rtu
