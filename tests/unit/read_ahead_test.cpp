// ReadAhead delivers exactly what its reader delivers, in order, across batch boundaries,
// up to and including the reader's error; and it can be dropped part-way.
#include "capture/read_ahead.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "capture/open_capture.hpp"
#include "capture_test_files.hpp"
#include "core/input_error.hpp"
#include "item_transcript.hpp"
#include "pinned_thread.hpp"

namespace rtu {
namespace {

using testing::ItemTranscript;

// Reads `reader` to its end; an error becomes the transcript's last line.
template <typename Reader>
std::vector<std::string> transcript_of(Reader& reader) {
  ItemTranscript t;
  try {
    while (reader.read(t)) {
    }
    if (reader.read(t)) t.lines.emplace_back("read after the end returned true");
  } catch (const InputError& e) {
    t.lines.push_back(std::string("error: ") + e.what());
    if (reader.read(t)) t.lines.emplace_back("read after the error returned true");
  }
  return t.lines;
}

void expect_same_items(const std::string& path) {
  SCOPED_TRACE(path);
  auto direct = open_capture(path, [](std::string_view) {});
  const auto expected = transcript_of(*direct);
  ReadAhead ahead(open_capture(path, [](std::string_view) {}));
  EXPECT_EQ(ahead.name(), path);
  const auto got = transcript_of(ahead);
  EXPECT_EQ(got, expected);
  EXPECT_FALSE(expected.empty());
}

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          fmt::format("rtuscope-read-ahead-{}-{}", ::getpid(), name))
      .string();
}

// Per-byte lines, several batches' worth, ending in a line that is not a capture line.
std::string write_long_capture(bool damaged) {
  const std::string path = temp_path(damaged ? "damaged.hex" : "long.hex");
  std::ofstream out(path);
  out << "# baud=9600 parity=E stop=1\n";
  const std::size_t lines = 3 * ReadAhead::kBatchItems + 17;
  for (std::size_t i = 0; i < lines; ++i) {
    out << fmt::format("{}.{:06d} {:02X}\n", i / 1000, (i % 1000) * 1000, i % 251);
  }
  if (damaged) out << "not a capture line\n";
  return path;
}

TEST(ReadAhead, DeliversWhatTheReaderDeliversForEveryBundledCapture) {
  const auto paths = testing::bundled_text_captures();
  for (const auto& path : paths) expect_same_items(path);
  EXPECT_GE(paths.size(), 10U);
}

TEST(ReadAhead, CrossesBatchesAndThrowsTheReadersErrorAfterEverythingBeforeIt) {
  for (const bool damaged : {false, true}) {
    const std::string path = write_long_capture(damaged);
    expect_same_items(path);
    ReadAhead ahead(open_capture(path, [](std::string_view) {}));
    const auto lines = transcript_of(ahead);
    EXPECT_EQ(lines.back().rfind("error: ", 0) == 0, damaged) << lines.back();
    EXPECT_GT(ahead.bytes_read(), 0U);
    EXPECT_EQ(ahead.input_size(), std::filesystem::file_size(path));
    std::remove(path.c_str());
  }
}

// Reads of one byte travel in shared items while they follow one another on one port with
// no error and no start time; each of those conditions ends a run. A scripted reader mixes
// them all, over several batches, and the transcript must be the reader's own.
class ScriptedReader final : public CaptureReader {
 public:
  bool read(CaptureConsumer& to) override {
    if (step_ == kSteps) {
      to.on_end(static_cast<Nanos>(10 * kSteps));
      ++step_;
      return true;
    }
    if (step_ > kSteps) return false;
    const std::size_t i = step_++;
    byte_ = static_cast<std::uint8_t>(i * 7);
    Chunk chunk;
    chunk.t_end = static_cast<Nanos>(10 * i);
    chunk.bytes = {&byte_, 1};
    chunk.origin = origin_++;
    if (i % 97 == 0) ++origin_;  // a line that held no read
    chunk.port = (i / 50) % 3 == 2 ? 1 : 0;
    if (i % 331 == 0) chunk.errors = {&error_, 1};
    if (i % 409 == 0) chunk.t_first_start = chunk.t_end - 5;
    if (i % 613 == 0) {
      chunk.bytes = {pair_, 2};
      origin_ += 1;
    }
    if (i % 1009 == 0) {
      to.on_frame({pair_, 2}, chunk.t_end, chunk.origin);
      return true;
    }
    to.on_chunk(chunk);
    return true;
  }
  [[nodiscard]] std::string name() const override { return "scripted"; }

  static constexpr std::size_t kSteps = 2 * ReadAhead::kBatchItems + 123;

 private:
  std::size_t step_ = 0;
  std::uint64_t origin_ = 0;
  std::uint8_t byte_ = 0;
  std::uint8_t error_ = kParityError;
  std::uint8_t pair_[2] = {0xAB, 0xCD};
};

TEST(ReadAhead, OneByteReadsComeOutAsTheReaderGaveThemWhateverEndsTheirRuns) {
  ScriptedReader direct;
  const auto expected = transcript_of(direct);
  ReadAhead ahead(std::make_unique<ScriptedReader>());
  EXPECT_EQ(transcript_of(ahead), expected);
  EXPECT_EQ(expected.size(), ScriptedReader::kSteps + 1);
}

// Asked for whole runs, ReadAhead hands each run of one-byte reads over in one call; the
// reads in it are those the reader gave, whatever ended the run (another port, a line error,
// a start time, a longer read, a record, a gap in the origins, the batch's end).
TEST(ReadAhead, WholeRunsOfOneByteReadsHoldTheReadsTheReaderGave) {
  ScriptedReader direct;
  const auto expected = transcript_of(direct);
  ReadAhead ahead(std::make_unique<ScriptedReader>(), {.whole_byte_runs = true});
  ItemTranscript got;
  std::size_t calls = 0;
  while (ahead.read(got)) ++calls;
  EXPECT_EQ(got.lines, expected);
  EXPECT_GT(got.runs, 100U);
  EXPECT_GT(got.reads_in_runs, ScriptedReader::kSteps / 2);
  // Each run was one read() call.
  EXPECT_EQ(calls, expected.size() - got.reads_in_runs + got.runs);
}

// Without records handed over, the reads and the end come out as before, the frame and
// noise records not at all; a consumer alongside still sees them.
TEST(ReadAhead, LeavesRecordsAsideWhenAskedButAConsumerAlongsideSeesThem) {
  ScriptedReader direct;
  auto expected = transcript_of(direct);
  ItemTranscript alongside;
  {
    ReadAhead ahead(std::make_unique<ScriptedReader>(),
                    {.alongside = &alongside, .hand_over_records = false});
    const auto got = transcript_of(ahead);
    EXPECT_EQ(alongside.lines, expected);
    std::erase_if(expected, [](const std::string& line) {
      return line.rfind("frame ", 0) == 0 || line.rfind("noise ", 0) == 0;
    });
    EXPECT_EQ(got, expected);
  }
  EXPECT_LT(expected.size(), alongside.lines.size());
}

TEST(ReadAhead, CanBeDroppedBeforeTheEnd) {
  const std::string path = write_long_capture(false);
  for (const int items : {0, 1, 5000}) {
    ReadAhead ahead(open_capture(path, [](std::string_view) {}));
    ItemTranscript t;
    for (int i = 0; i < items; ++i) ASSERT_TRUE(ahead.read(t));
    EXPECT_EQ(t.lines.size(), static_cast<std::size_t>(items));
  }  // the destructor stops the reading thread, which may be waiting for a free batch
  std::remove(path.c_str());
}

// A consumer alongside sees every item, the reader's error included, as a direct read gives
// them (on the reading thread), and the reader answers for the whole capture once reading
// ended: never before.
TEST(ReadAhead, AConsumerAlongsideSeesEveryItemAndTheReaderIsAskedOnlyAtTheEnd) {
  for (const bool damaged : {false, true}) {
    const std::string path = write_long_capture(damaged);
    auto direct = open_capture(path, [](std::string_view) {});
    auto expected = transcript_of(*direct);
    // The consumer alongside does not see read() return or throw: only the items.
    if (damaged) expected.pop_back();
    ItemTranscript alongside;
    ReadAhead ahead(open_capture(path, [](std::string_view) {}), {.alongside = &alongside});
    ItemTranscript first;
    ASSERT_TRUE(ahead.read(first));
    EXPECT_FALSE(ahead.ended());
    EXPECT_THROW((void)ahead.source(), std::logic_error);
    const auto rest = transcript_of(ahead);
    EXPECT_TRUE(ahead.ended());
    EXPECT_EQ(alongside.lines, expected);
    EXPECT_EQ(first.lines.size() + rest.size(), expected.size() + (damaged ? 1U : 0U));
    const CaptureReader& source = ahead.source();
    ASSERT_TRUE(source.declared_settings().has_value());
    EXPECT_EQ(source.declared_settings()->baud, 9600U);
    EXPECT_EQ(source.bytes_read(), ahead.bytes_read());
    std::remove(path.c_str());
  }
}

// A reader that notes the nice value of the thread it is read on, and ends at once.
class NiceNotingReader final : public CaptureReader {
 public:
  explicit NiceNotingReader(int& nice) : nice_(nice) {}
  bool read(CaptureConsumer& /*to*/) override {
    nice_ = testing::nice_of_this_thread();
    return false;
  }
  [[nodiscard]] std::string name() const override { return "nice-noting"; }

 private:
  int& nice_;
};

// The nice value a ReadAhead's reading thread reads at, made on a thread that may run on
// one core only (the reading thread inherits that), relative to the maker's.
int reading_nice_on_one_core(std::size_t yields_among_threads) {
  int relative = 0;
  testing::on_new_thread(1, [&] {
    const int own = testing::nice_of_this_thread();
    int nice = own;
    {
      ReadAhead ahead(std::make_unique<NiceNotingReader>(nice),
                      {.whole_byte_runs = true, .yields_among_threads = yields_among_threads});
      ItemTranscript t;
      while (ahead.read(t)) {
      }
    }
    relative = nice - own;
  });
  return relative;
}

// Three threads on one core: a reading thread that is the lightest of three (a
// FramingAhead's reader) yields; one of no such pipeline, or alone, does not.
TEST(ReadAhead, TheReadingThreadYieldsWhenAskedAndTheCoresAreFewerThanTheThreads) {
  if (testing::nice_of_this_thread() + 3 > 19) {
    GTEST_SKIP() << "already at the lowest priority";
  }
  EXPECT_EQ(reading_nice_on_one_core(3), 3);
  EXPECT_EQ(reading_nice_on_one_core(0), 0);
  EXPECT_EQ(reading_nice_on_one_core(1), 0);
}

}  // namespace
}  // namespace rtu
