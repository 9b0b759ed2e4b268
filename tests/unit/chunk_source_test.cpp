// ChunkSource::read_many() gathers one-byte reads into runs: whatever the room it is given,
// the reads come out as read() gives them, one by one, in order, with every kind of chunk
// that ends a run (a longer read, a line error, a comment line between, the end, damage),
// and what was read before damage comes out before the error.
#include "capture/chunk_source.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "capture/open_capture.hpp"
#include "capture_test_files.hpp"
#include "core/input_error.hpp"
#include "item_transcript.hpp"

namespace rtu {
namespace {

using testing::ItemTranscript;

// Reads `path` to its end, with read() when `room` is 0, else read_many(room); an error
// becomes the last line.
ItemTranscript transcript_of(const std::string& path, std::size_t room) {
  auto reader = open_capture(path, [](std::string_view) {});
  ItemTranscript t;
  const auto read = [&] { return room == 0 ? reader->read(t) : reader->read_many(t, room); };
  try {
    while (read()) {
    }
    if (read()) t.lines.emplace_back("read after the end returned true");
  } catch (const InputError& e) {
    t.lines.push_back(std::string("error: ") + e.what());
  }
  return t;
}

// Per-byte lines with everything that ends a run of one-byte reads among them.
std::string per_byte_capture(const testing::TempDir& dir, bool damaged) {
  std::string text = "# baud=9600 parity=E stop=1\n";
  for (int i = 0; i < 9000; ++i) {
    const int ms = i * 2;
    if (i % 997 == 5) text += "# a comment between two reads\n";
    if (i % 1201 == 7) {
      text += fmt::format("{}.{:03d} 01 02 03\n", ms / 1000, ms % 1000);  // a longer read
      continue;
    }
    text += fmt::format("{}.{:03d} {:02X}\n", ms / 1000, ms % 1000, i % 256);
  }
  if (damaged) text += "0.5 not hex\n";
  return dir.write(damaged ? "damaged.hex" : "clean.hex", text);
}

TEST(ChunkSource, ReadManyGivesTheReadsOfReadWhateverItsRoom) {
  const testing::TempDir dir;
  std::vector<std::string> paths = testing::bundled_text_captures();
  paths.push_back(per_byte_capture(dir, false));
  paths.push_back(per_byte_capture(dir, true));
  for (const auto& path : paths) {
    SCOPED_TRACE(path);
    const auto expected = transcript_of(path, 0).lines;
    EXPECT_FALSE(expected.empty());
    for (const std::size_t room : {1U, 2U, 3U, 7U, 4096U, 100000U}) {
      SCOPED_TRACE(room);
      const ItemTranscript got = transcript_of(path, room);
      EXPECT_EQ(got.lines, expected);
    }
  }
  // The per-byte capture's reads came in runs, and its damage after all of them.
  const ItemTranscript clean = transcript_of(paths[paths.size() - 2], 4096);
  EXPECT_GT(clean.reads_in_runs, 8900U);
  EXPECT_LT(clean.runs, 60U);
  const ItemTranscript damaged = transcript_of(paths.back(), 4096);
  EXPECT_EQ(damaged.lines.back().rfind("error: ", 0), 0U) << damaged.lines.back();
  EXPECT_EQ(damaged.reads_in_runs, clean.reads_in_runs);
}

// A source whose reads are scripted: one-byte reads whose origins jump now and then, and
// longer reads. It hands one-byte reads over through next_byte_reads() as far as their
// origins follow one another, so a call can begin where the run before it cannot go on.
class ScriptedSource final : public ChunkSource {
 public:
  struct Read {
    std::vector<std::uint8_t> bytes;
    Nanos t_end = 0;
    std::uint64_t origin = 0;
  };
  explicit ScriptedSource(std::vector<Read> reads) : reads_(std::move(reads)) {}

  bool next(Chunk& out) override {
    if (at_ == reads_.size()) return false;
    const Read& read = reads_[at_++];
    out = Chunk{};
    out.t_end = read.t_end;
    out.bytes = read.bytes;
    out.origin = read.origin;
    return true;
  }
  [[nodiscard]] std::string name() const override { return "scripted"; }

 protected:
  std::size_t next_byte_reads(std::uint8_t* bytes, Nanos* t_ends, std::size_t room,
                              std::uint64_t& first_origin) override {
    std::size_t got = 0;
    while (got < room && at_ < reads_.size() && reads_[at_].bytes.size() == 1) {
      const Read& read = reads_[at_];
      if (got > 0 && read.origin != first_origin + got) break;
      if (got == 0) first_origin = read.origin;
      bytes[got] = read.bytes[0];
      t_ends[got] = read.t_end;
      ++got;
      ++at_;
    }
    return got;
  }

 private:
  std::vector<Read> reads_;
  std::size_t at_ = 0;
};

TEST(ChunkSource, RunsEndWhereTheReadsAReaderHandsOverDoNotFollowOn) {
  std::vector<ScriptedSource::Read> script;
  std::uint64_t origin = 1;
  for (int i = 0; i < 500; ++i) {
    // Lines between (comments, say), now and then two such jumps in a row: a reader's run
    // can then begin with a jump right after the read that next() gave.
    origin += i % 37 == 11 || i % 37 == 12 || i % 53 == 20 ? 3U : 1U;
    if (i % 101 == 50) {
      script.push_back({{0x01, 0x02}, i * 1000, origin});
    } else {
      script.push_back({{static_cast<std::uint8_t>(i)}, i * 1000, origin});
    }
  }
  ScriptedSource one_by_one(script);
  ItemTranscript expected;
  while (one_by_one.read(expected)) {
  }
  ASSERT_EQ(expected.lines.size(), script.size());
  for (const std::size_t room : {1U, 2U, 5U, 64U, 4096U}) {
    SCOPED_TRACE(room);
    ScriptedSource source(script);
    ItemTranscript got;
    while (source.read_many(got, room)) {
    }
    EXPECT_EQ(got.lines, expected.lines);
    if (room >= 5) {
      EXPECT_LT(got.runs, script.size() / 2);
    }
  }
}

}  // namespace
}  // namespace rtu
