// A first look (identification's sample) is taken in the decoding pass itself, and the sink
// still gets exactly what it gets without one: the records held meanwhile come back with
// every field and byte, in order, with the decided times between them; the look ends after
// as many records as it wants, at the capture's end or damage, or where the held records
// reach their bound; and it concludes before the sink hears of the capture.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "capture_test_files.hpp"
#include "core/input_error.hpp"
#include "pipeline/first_look_gate.hpp"
#include "pipeline/held_records.hpp"
#include "pipeline/replay.hpp"
#include "record_transcript.hpp"

namespace rtu {
namespace {

// Every call it gets, as a line of text.
class Lines final : public PairingInput {
 public:
  void on_capture(const CaptureInfo& info) override {
    lines.push_back(fmt::format("capture {}", info.source));
  }
  void on_record(Record& record) override {
    lines.push_back(testing::describe_record(record));
    if (record.kind == RecordKind::kFrame) ++frames;
  }
  void advance(Nanos now) override { lines.push_back(fmt::format("advance {}", now)); }
  void on_finish() override { lines.emplace_back("finish"); }
  void on_break() override { lines.emplace_back("break"); }

  std::vector<std::string> lines;
  std::uint64_t frames = 0;
};

// Looks at `wanted` records, and notes what the sink had got by the time it concluded.
class CountingLook final : public FirstLook {
 public:
  CountingLook(std::uint64_t wanted, const Lines& sink) : wanted_(wanted), sink_(sink) {}
  PairingInput& start_look(const CaptureInfo& /*info*/) override {
    ++starts;
    return seen;
  }
  [[nodiscard]] bool seen_enough() const override { return seen.frames >= wanted_; }
  void conclude(SampleEnd why) override {
    ++conclusions;
    end = why;
    sink_lines_then = sink_.lines.size();
    seen_finished = !seen.lines.empty() && seen.lines.back() == "finish";
  }

  Lines seen;
  int starts = 0;
  int conclusions = 0;
  SampleEnd end = SampleEnd::kCaptureEnd;
  std::size_t sink_lines_then = std::numeric_limits<std::size_t>::max();
  bool seen_finished = false;

 private:
  std::uint64_t wanted_;
  const Lines& sink_;
};

Record frame_of(std::uint64_t seq, std::uint16_t size) {
  Record r;
  r.seq = seq;
  r.kind = seq % 5 == 4 ? RecordKind::kNoise : RecordKind::kFrame;
  r.t_start = static_cast<Nanos>(seq) * 1000 + 7;
  r.t_end = r.t_start + 900;
  r.gap_before = seq % 3 == 0 ? kUnknownTime : 100 + static_cast<Nanos>(seq);
  r.origin = 40 + seq;
  r.size = size;
  for (std::uint16_t i = 0; i < size; ++i)
    r.storage.at(i) = static_cast<std::uint8_t>(seq * 31 + i);
  r.line_errors = static_cast<std::uint8_t>(seq % 4);
  r.shape_fit = static_cast<std::uint8_t>(seq % 3);
  r.crc_ok = seq % 2 == 0;
  if (seq % 7 == 0) r.issues.add(IssueId::kTimeout);
  return r;
}

TEST(HeldRecords, TellsEveryRecordAsHeldWithTheLastOfEachRunOfDecidedTimes) {
  HeldRecords held;
  Lines expected;
  for (std::uint64_t seq = 0; seq < 3000; ++seq) {
    Record r = frame_of(seq, static_cast<std::uint16_t>(seq % (kMaxAdu + 1)));
    held.hold(r);
    expected.on_record(r);
    // Runs of 0-2 decided times: the tracker's verdicts depend only on the last of a run.
    for (std::uint64_t k = 0; k < seq % 3; ++k)
      held.hold_advance(r.t_end + 10 + static_cast<Nanos>(k));
    if (seq % 3 != 0) expected.advance(r.t_end + 10 + static_cast<Nanos>(seq % 3) - 1);
    if (seq % 100 == 50) {  // a break comes after the decided time before it
      held.hold_break();
      expected.on_break();
    }
  }
  EXPECT_GT(held.bytes_held(), 3000U * 56);  // several blocks' worth
  Lines told;
  held.tell(told);
  EXPECT_EQ(told.lines, expected.lines);
  EXPECT_EQ(held.bytes_held(), 0U);
  Lines again;
  held.tell(again);
  EXPECT_TRUE(again.lines.empty());
}

// Fields are held as differences from the record before: any value must come back, however
// far it lies from the last one (times unknown, negative or at the ends of their range,
// sequence numbers and origins that jump back), and decided times anywhere.
TEST(HeldRecords, TellsFieldsFarFromTheRecordBeforeAsHeld) {
  std::mt19937_64 random(11);
  const auto any_time = [&random]() -> Nanos {
    switch (random() % 6) {
      case 0: return kUnknownTime;
      case 1: return std::numeric_limits<Nanos>::max() - static_cast<Nanos>(random() % 3);
      case 2: return std::numeric_limits<Nanos>::min() + static_cast<Nanos>(random() % 3);
      case 3: return -static_cast<Nanos>(random() % 1000000);
      default: return static_cast<Nanos>(random() >> 1U);
    }
  };
  HeldRecords held;
  Lines expected;
  for (int i = 0; i < 5000; ++i) {
    Record r;
    r.seq = i % 4 == 0 ? random() : static_cast<std::uint64_t>(i);
    r.origin = random() >> (random() % 64);
    r.t_start = any_time();
    // Often an end right after the start, where the start has a next value.
    const bool has_next = r.t_start < std::numeric_limits<Nanos>::max();
    r.t_end = random() % 2 == 0 || !has_next ? any_time() : r.t_start + 1;
    r.gap_before = any_time();
    r.kind = random() % 2 == 0 ? RecordKind::kNoise : RecordKind::kFrame;
    r.size = static_cast<std::uint16_t>(random() % (kMaxAdu + 1));
    for (std::uint16_t k = 0; k < r.size; ++k)
      r.storage.at(k) = static_cast<std::uint8_t>(random());
    r.line_errors = static_cast<std::uint8_t>(random() % 16);
    r.shape_fit = static_cast<std::uint8_t>(random() % 4);
    r.crc_ok = random() % 2 == 0;
    for (unsigned k = 0; k < static_cast<unsigned>(IssueId::kCount); ++k) {
      if (random() % 8 == 0) r.issues.add(static_cast<IssueId>(k));
    }
    held.hold(r);
    expected.on_record(r);
    if (random() % 3 == 0) {
      const Nanos now = any_time();
      held.hold_advance(now);
      expected.advance(now);
    }
  }
  Lines told;
  held.tell(told);
  ASSERT_EQ(told.lines.size(), expected.lines.size());
  for (std::size_t i = 0; i < told.lines.size(); ++i)
    ASSERT_EQ(told.lines[i], expected.lines[i]) << i;
}

// The decoding of `path` into a transcript of the sink's calls, with `look` (may be null).
std::vector<std::string> replayed(const std::string& path, FirstLook* look, bool frame_ahead,
                                  Lines& sink) {
  ReplayOptions options;
  options.show_warnings = false;
  options.frame_ahead = frame_ahead;
  options.first_look = look;
  try {
    replay_capture(path, options, sink);
  } catch (const InputError& e) {
    sink.lines.push_back(std::string("error: ") + e.what());
  }
  return sink.lines;
}

// Polling read by read, longer than a few of the framing's batches, ending in damage.
std::string write_damaged_capture(const testing::TempDir& dir) {
  std::string text = "# baud=9600 parity=E stop=1\n";
  for (std::size_t i = 0; i < 20000; ++i) {
    const std::size_t ms = i * 100;
    text += fmt::format("{}.{:03d}000 01 03 00 00 00 01 84 0A\n", ms / 1000, ms % 1000);
    if (i % 7 != 3)
      text += fmt::format("{}.{:03d}000 01 03 02 00 2A 39 9B\n", ms / 1000, ms % 1000 + 30);
  }
  text += "not a capture line\n";
  return dir.write("damaged.hex", text);
}

TEST(FirstLookGate, SinkGetsWhatItGetsWithoutALookAfterTheLookConcluded) {
  const testing::TempDir dir;
  auto paths = testing::bundled_text_captures();
  paths.push_back(write_damaged_capture(dir));
  for (const auto& path : paths) {
    for (const bool frame_ahead : {true, false}) {
      Lines plain;
      const auto expected = replayed(path, nullptr, frame_ahead, plain);
      ASSERT_GT(plain.frames, 2U) << path;
      for (const std::uint64_t wanted : {std::uint64_t{1}, std::uint64_t{30}, plain.frames + 1}) {
        SCOPED_TRACE(fmt::format("{} frame_ahead={} wanted={}", path, frame_ahead, wanted));
        Lines sink;
        CountingLook look(wanted, sink);
        EXPECT_EQ(replayed(path, &look, frame_ahead, sink), expected);
        EXPECT_EQ(look.starts, 1);
        EXPECT_EQ(look.conclusions, 1);
        EXPECT_EQ(look.sink_lines_then, 0U);  // not even the capture's start
        EXPECT_TRUE(look.seen_finished);
        // The look saw as many frames as it wanted, or all there were (the tracker it feeds
        // here is none, so it sees each frame as the framing made it).
        EXPECT_EQ(look.seen.frames, std::min(wanted, plain.frames));
        // It ended on enough frames where there were that many (the last one included).
        EXPECT_EQ(look.end, wanted <= plain.frames ? SampleEnd::kEnough : SampleEnd::kCaptureEnd);
      }
    }
  }
}

// A look that never has enough ends where the held records reach their bound, and the
// pairing still gets every record in order.
TEST(FirstLookGate, EndsTheLookWhereTheHeldRecordsReachTheirBound) {
  Lines pairing;
  CountingLook look(std::numeric_limits<std::uint64_t>::max(), pairing);
  FirstLookGate gate(&look, pairing);
  gate.on_capture(CaptureInfo{});
  const std::uint64_t records = FirstLook::kMaxHeldBytes / kMaxAdu + 20000;
  for (std::uint64_t seq = 0; seq < records; ++seq) {
    Record r = frame_of(seq, kMaxAdu);
    gate.on_record(r);
  }
  gate.on_finish();
  EXPECT_EQ(look.conclusions, 1);
  EXPECT_EQ(look.end, SampleEnd::kHeldBound);
  EXPECT_EQ(look.sink_lines_then, 0U);
  const std::uint64_t seen = look.seen.lines.size() - 2;  // less its capture and finish lines
  EXPECT_LT(seen, records);
  EXPECT_GE(seen * (kMaxAdu + 56), FirstLook::kMaxHeldBytes - 512 * 1024);
  ASSERT_EQ(pairing.lines.size(), records + 2);
  EXPECT_EQ(pairing.lines.front(), "capture ");
  for (std::uint64_t seq = 0; seq < records; seq += 997) {
    EXPECT_EQ(pairing.lines[seq + 1], testing::describe_record(frame_of(seq, kMaxAdu)));
  }
  EXPECT_EQ(pairing.lines.back(), "finish");
}

}  // namespace
}  // namespace rtu
