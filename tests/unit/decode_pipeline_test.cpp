// DecodePipeline::push_byte_reads() tells the pairing what push() of each read tells it: the
// same records, and before each record and at the end, the line decided at least as far.
// The runs skip the moves of the decided time that a later one covers, so only how far it
// got by each record can be compared, not every move. And a long read's bytes count from
// when they were on the wire, not from when the read completed.
#include "pipeline/decode_pipeline.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "core/crc16.hpp"

namespace rtu {
namespace {

// Each record as a line, with how far the line was decided when it came; the furthest at
// the end.
class DecidedTranscript final : public PairingInput {
 public:
  void advance(Nanos now) override { decided_ = std::max(decided_, now); }
  void on_record(Record& r) override {
    lines.push_back(fmt::format("decided={} kind={} t={}..{} gap={} origin={} issues={:x} {:02x}",
                                decided_, static_cast<int>(r.kind), r.t_start, r.t_end,
                                r.gap_before, r.origin, r.issues.bits(), fmt::join(r.bytes(), "")));
  }
  void on_finish() override { lines.push_back(fmt::format("finish decided={}", decided_)); }
  void on_break() override { lines.emplace_back("break"); }

  std::vector<std::string> lines;

 private:
  Nanos decided_ = kUnknownTime;
};

std::vector<std::uint8_t> with_crc(std::vector<std::uint8_t> pdu) {
  const std::uint16_t crc = crc16(pdu);
  pdu.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  pdu.push_back(static_cast<std::uint8_t>(crc >> 8U));
  return pdu;
}

struct ByteRead {
  std::uint8_t byte = 0;
  Nanos t_end = 0;
};

// Polling at 9600 baud, a byte a read: short reads, long writes (fc 16, whose bytes keep a
// frame waiting for a long time), unanswered requests, and now and then a few reads stamped
// before the one before them (a clock stepping back for a while), inside frames too.
std::vector<ByteRead> polling_reads() {
  std::mt19937 random(7);
  const Nanos char_time = LineSettings{}.char_time();
  std::vector<ByteRead> reads;
  Nanos t = 0;
  int back_left = 0;  // reads still to be stamped `back` early
  Nanos back = 0;
  for (int poll = 0; poll < 300; ++poll) {
    std::vector<std::uint8_t> request;
    std::vector<std::uint8_t> response;
    if (poll % 3 == 0) {
      request = {0x02, 0x10, 0x00, 0x00, 0x00, 0x60, 0xC0};
      for (int i = 0; i < 0xC0; ++i) request.push_back(static_cast<std::uint8_t>(random()));
      response = {0x02, 0x10, 0x00, 0x00, 0x00, 0x60};
    } else {
      request = {0x01, 0x03, 0x00, 0x00, 0x00, 0x01};
      response = {0x01, 0x03, 0x02, 0x00, static_cast<std::uint8_t>(poll)};
    }
    const auto send = [&](const std::vector<std::uint8_t>& frame) {
      for (const std::uint8_t byte : with_crc(frame)) {
        t += char_time;
        if (back_left == 0 && random() % 41 == 0) {
          back_left = 1 + static_cast<int>(random() % 6);
          back = static_cast<Nanos>(random() % 200) * kNanosPerMilli;
        }
        reads.push_back({byte, back_left > 0 ? t - back : t});
        if (back_left > 0) --back_left;
      }
    };
    send(request);
    t += 5 * kNanosPerMilli;
    if (poll % 5 != 2) send(response);
    t += static_cast<Nanos>(20 + random() % 120) * kNanosPerMilli;
  }
  return reads;
}

PipelineOptions options() {
  PipelineOptions opts;
  opts.timing_resolution = 0;
  opts.response_timeout = 30 * kNanosPerMilli;  // shorter than a long write takes to send
  return opts;
}

TEST(DecodePipeline, RunsOfOneByteReadsTellThePairingWhatTheReadsOneByOneTell) {
  const std::vector<ByteRead> reads = polling_reads();
  DecidedTranscript expected;
  {
    DecodePipeline pipeline(options(), expected);
    for (std::size_t i = 0; i < reads.size(); ++i) {
      Chunk chunk;
      chunk.t_end = reads[i].t_end;
      chunk.bytes = {&reads[i].byte, 1};
      chunk.origin = i;
      pipeline.push(chunk);
    }
    pipeline.finish();
  }
  EXPECT_GT(expected.lines.size(), 500U);

  std::vector<std::uint8_t> bytes;
  std::vector<Nanos> t_ends;
  for (const ByteRead& read : reads) {
    bytes.push_back(read.byte);
    t_ends.push_back(read.t_end);
  }
  for (const std::size_t run : {1U, 3U, 64U, 100000U}) {
    SCOPED_TRACE(run);
    DecidedTranscript got;
    DecodePipeline pipeline(options(), got);
    for (std::size_t first = 0; first < reads.size(); first += run) {
      const std::size_t size = std::min(run, reads.size() - first);
      pipeline.push_byte_reads(
          ByteReads{std::span(bytes).subspan(first, size), t_ends.data() + first, first, 0});
    }
    pipeline.finish();
    EXPECT_EQ(got.lines, expected.lines);
  }
}

// What the pairing made of each frame: its role, transaction and issues.
class Verdicts final : public RecordSink {
 public:
  void on_record(Record& r) override {
    if (r.kind == RecordKind::kFrame) frames.push_back(r);
  }
  std::vector<Record> frames;
};

// A request read byte by byte, then its answer of 25 bytes in one read (a reader or adapter
// that delivered 29 ms of bytes at once, at 9600 baud), starting `answer_after` after the
// request ended. The read completes well after the response timeout either way.
std::vector<Record> request_and_long_answer(Nanos answer_after) {
  const Nanos char_time = LineSettings{}.char_time();
  PipelineOptions opts;
  opts.timing_resolution = kNanosPerMilli;
  opts.response_timeout = 100 * kNanosPerMilli;
  Verdicts verdicts;
  DecodePipeline pipeline(opts, verdicts);
  const std::vector<std::uint8_t> request = with_crc({0x01, 0x03, 0x00, 0x00, 0x00, 0x0A});
  std::vector<std::uint8_t> answer = {0x01, 0x03, 0x14};
  for (int i = 0; i < 20; ++i) answer.push_back(static_cast<std::uint8_t>(i));
  answer = with_crc(answer);
  Nanos t = kNanosPerSecond;
  for (std::size_t i = 0; i < request.size(); ++i) {
    t += char_time;
    Chunk chunk;
    chunk.t_end = t;
    chunk.bytes = {&request[i], 1};
    pipeline.push(chunk);
  }
  Chunk long_read;
  long_read.t_end = t + answer_after + static_cast<Nanos>(answer.size()) * char_time;
  long_read.bytes = answer;
  pipeline.push(long_read);
  pipeline.finish();
  return verdicts.frames;
}

TEST(DecodePipeline, AnAnswerThatStartsBeforeTheTimeoutInALongReadIsPaired) {
  // The moment before the long read is idle, but not at its end: its first bytes were on the
  // wire 29 ms before, 1 ms before the deadline.
  const auto in_time = request_and_long_answer(99 * kNanosPerMilli);
  ASSERT_EQ(in_time.size(), 2U);
  EXPECT_FALSE(in_time[0].issues.has(IssueId::kTimeout));
  EXPECT_FALSE(in_time[1].issues.has(IssueId::kLate));
  EXPECT_EQ(in_time[1].role, Role::kResponse);
  EXPECT_NE(in_time[0].txn, -1);
  EXPECT_EQ(in_time[0].txn, in_time[1].txn);
  EXPECT_EQ(in_time[1].latency, 99 * kNanosPerMilli);

  // Starting 1 ms after the deadline, the same read's answer is late.
  const auto late = request_and_long_answer(101 * kNanosPerMilli);
  ASSERT_EQ(late.size(), 2U);
  EXPECT_TRUE(late[0].issues.has(IssueId::kTimeout));
  EXPECT_TRUE(late[1].issues.has(IssueId::kLate));
}

}  // namespace
}  // namespace rtu
