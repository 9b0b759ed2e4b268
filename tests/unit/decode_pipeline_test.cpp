// DecodePipeline::push_byte_reads() tells the pairing what push() of each read tells it: the
// same records, and before each record and at the end, the line decided at least as far.
// The runs skip the moves of the decided time that a later one covers, so only how far it
// got by each record can be compared, not every move.
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

}  // namespace
}  // namespace rtu
