// Framing on sick buses: what the per-byte timestamps show is evidence the framer must not
// override; turnaround glitches never hide the timing of the frames around them; the two
// directions of a link are framed apart.
#include <gtest/gtest.h>

#include "bus_builder.hpp"
#include "framing/framer.hpp"
#include "pipeline/decode_pipeline.hpp"

namespace rtu {
namespace {

using test::BusBuilder;
using test::CollectingSink;
using test::with_crc;

constexpr Nanos kUs = kNanosPerMicro;
constexpr Nanos kMs = kNanosPerMilli;

std::vector<std::uint8_t> bytes_of(const Record& r) {
  return {r.bytes().begin(), r.bytes().end()};
}

// Slave 5 polled at 19200 baud (t1.5 0.86 ms, t3.5 2.0 ms): the bus several tests disturb.
struct PolledSlave {
  LineSettings line{19200};
  std::vector<std::uint8_t> request = with_crc({0x05, 0x03, 0x00, 0x10, 0x00, 0x01});
  std::vector<std::uint8_t> response = with_crc({0x05, 0x03, 0x02, 0x01, 0x02});
};

std::vector<Record> frame(const std::vector<Chunk>& chunks, const LineSettings& line,
                          Nanos resolution) {
  CollectingSink sink;
  Framer framer(FramerConfig{line, resolution, false, true}, sink);
  for (const auto& c : chunks) framer.push(c);
  framer.finish();
  return sink.records;
}

TEST(SickBusFraming, DamagedRequestSentInOneGoStaysOneFrame) {
  // 01 03 00 42 00 08 with the function code's bit 2 flipped (03 → 07): FC07's request is
  // 4 bytes, but the bytes came back to back, so no frame boundary can be inside.
  const auto good = with_crc({0x01, 0x03, 0x00, 0x42, 0x00, 0x08});
  auto damaged = good;
  damaged[1] = 0x07;
  const auto answer = with_crc({0x01, 0x03, 0x10, 0, 1, 0, 2, 0, 3, 0, 4, 0, 5, 0, 6, 0, 7, 0, 8});
  BusBuilder bus;
  bus.add(good, 0).add(answer, 5 * kMs).add(damaged, 50 * kMs).add(good, 1000 * kMs);
  const auto records = frame(bus.per_byte(), bus.line(), kUs);
  ASSERT_EQ(records.size(), 4U);
  EXPECT_EQ(bytes_of(records[2]), damaged);
  EXPECT_FALSE(records[2].crc_ok);
  EXPECT_EQ(bytes_of(records[3]), good) << "the clean request after the damage";
  EXPECT_TRUE(records[3].crc_ok);
}

TEST(SickBusFraming, GlitchAfterResponseIsTheSendersAndDoesNotHideT35) {
  const PolledSlave polled;
  const auto& [line, request, response] = polled;
  BusBuilder bus(line);
  // The master polls again 1 ms after the glitch: less than t3.5 (1.75 ms) after the
  // response, whatever the glitch byte.
  bus.add(request, 0).add(response, 3 * kMs).add({0xFE}, 100 * kUs).add(request, 1 * kMs);
  const auto records = frame(bus.per_byte(), line, kUs);
  ASSERT_EQ(records.size(), 4U);
  EXPECT_EQ(records[2].kind, RecordKind::kNoise);
  EXPECT_TRUE(records[2].issues.has(IssueId::kTurnaroundGlitch));
  EXPECT_EQ(records[3].kind, RecordKind::kFrame);
  EXPECT_TRUE(records[3].issues.has(IssueId::kT35));
}

TEST(SickBusFraming, GlitchDoesNotInventAViolation) {
  const PolledSlave polled;
  const auto& [line, request, response] = polled;
  BusBuilder bus(line);
  bus.add(request, 0).add(response, 3 * kMs).add({0x00}, 50 * kUs).add(request, 20 * kMs);
  const auto records = frame(bus.per_byte(), line, kUs);
  ASSERT_EQ(records.size(), 4U);
  EXPECT_TRUE(records[2].issues.has(IssueId::kTurnaroundGlitch));
  EXPECT_FALSE(records[3].issues.has(IssueId::kT35));
}

TEST(SickBusFraming, ByteFarFromAFrameIsPlainNoise) {
  LineSettings line;
  line.baud = 19200;
  const auto request = with_crc({0x05, 0x03, 0x00, 0x10, 0x00, 0x01});
  BusBuilder bus(line);
  bus.add(request, 0).add({0xFE}, 5 * kMs).add(request, 20 * kMs);
  const auto records = frame(bus.per_byte(), line, kUs);
  ASSERT_EQ(records.size(), 3U);
  EXPECT_EQ(records[1].kind, RecordKind::kNoise);
  EXPECT_FALSE(records[1].issues.has(IssueId::kTurnaroundGlitch));
}

TEST(SickBusFraming, UsbPacketBoundaryInsideAFrameTeachesTheResolution) {
  LineSettings line;
  line.baud = 115200;
  const auto request = with_crc({0x11, 0x03, 0x00, 0x00, 0x00, 0x30});
  std::vector<std::uint8_t> body = {0x11, 0x03, 0x60};
  for (int i = 0; i < 0x60; ++i) body.push_back(static_cast<std::uint8_t>(i));
  const std::uint16_t crc = crc16(body);
  body.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  body.push_back(static_cast<std::uint8_t>(crc >> 8U));
  BusBuilder bus(line);
  for (int i = 0; i < 20; ++i) bus.add(request, 30 * kMs).add(body, 300 * kUs);
  CollectingSink sink;
  // The port claimed 1 ms; the adapter holds bytes for 16 ms, 16 bytes a packet.
  Framer framer(FramerConfig{line, kMs, false, true}, sink);
  for (const auto& c : bus.usb(16 * kMs, 16)) framer.push(c);
  framer.finish();
  ASSERT_EQ(sink.records.size(), 40U);
  for (const auto& r : sink.records) {
    EXPECT_TRUE(r.crc_ok);
    EXPECT_FALSE(r.issues.has(IssueId::kT15)) << "a packet boundary is not a pause";
  }
  EXPECT_GE(framer.resolution(), 10 * kMs);
}

TEST(SickBusFraming, PerByteSourceKeepsRealPausesInsideFrames) {
  LineSettings line;
  line.baud = 19200;
  BusBuilder bus(line);
  const auto response = with_crc({0x05, 0x03, 0x04, 0x01, 0x02, 0x03, 0x04});
  const std::vector<std::uint8_t> head(response.begin(), response.begin() + 4);
  const std::vector<std::uint8_t> tail(response.begin() + 4, response.end());
  bus.add(with_crc({0x05, 0x03, 0x00, 0x00, 0x00, 0x02}), 0).add(head, 5 * kMs).add(tail, 1 * kMs);
  CollectingSink sink;
  Framer framer(FramerConfig{line, kUs, false, true}, sink);
  for (const auto& c : bus.per_byte()) framer.push(c);
  framer.finish();
  ASSERT_EQ(sink.records.size(), 2U);
  EXPECT_TRUE(sink.records[1].crc_ok);
  EXPECT_TRUE(sink.records[1].issues.has(IssueId::kT15));
  EXPECT_EQ(framer.resolution(), kUs);
}

// A poll and its answer, then `first`, `second` 1.2 ms after it (more than t1.5, less than
// t3.5), and the next poll, framed from per-byte timestamps.
std::vector<Record> around_a_t15_pause(const std::vector<std::uint8_t>& first,
                                       const std::vector<std::uint8_t>& second) {
  const PolledSlave polled;
  BusBuilder bus(polled.line);
  bus.add(polled.request, 0).add(polled.response, 3 * kMs);
  bus.add(first, 20 * kMs).add(second, 1200 * kUs).add(polled.request, 20 * kMs);
  return frame(bus.per_byte(), polled.line, kUs);
}

// A pause longer than t1.5 that the per-byte timestamps show, inside bytes that hold no
// valid frame: two senders, or one that stopped. Each side is a record of its own.
TEST(SickBusFraming, GlitchThenADamagedFrameAfterMoreThanT15AreTwoRecords) {
  auto damaged = PolledSlave{}.request;
  damaged[3] ^= 0x04U;
  const std::vector<std::uint8_t> glitch = {0x00, 0x00};
  const auto records = around_a_t15_pause(glitch, damaged);
  ASSERT_EQ(records.size(), 5U);
  EXPECT_EQ(records[2].kind, RecordKind::kNoise);
  EXPECT_EQ(bytes_of(records[2]), glitch);
  EXPECT_EQ(records[3].kind, RecordKind::kFrame);
  EXPECT_EQ(bytes_of(records[3]), damaged);
  EXPECT_FALSE(records[3].crc_ok);
  EXPECT_TRUE(records[4].crc_ok);
}

// On a bus with broadcasts a 0x00 glitch reads as one's address; before a read's function
// code it is none (a broadcast only writes), so its length rule does not hold the glitch and
// the fragment after the pause together.
TEST(SickBusFraming, ZeroGlitchBeforeAReadIsNoBroadcastThatSpansAPause) {
  // Slave 3: after the glitch its address reads as function 03, a read.
  const LineSettings line{19200};
  const auto request = with_crc({0x03, 0x03, 0x00, 0x10, 0x00, 0x01});
  const auto response = with_crc({0x03, 0x03, 0x02, 0x01, 0x02});
  const auto broadcast = with_crc({0x00, 0x06, 0x00, 0x01, 0x00, 0x07});
  const std::vector<std::uint8_t> glitch = {0x00};
  const std::vector<std::uint8_t> fragment(request.begin(), request.begin() + 4);
  BusBuilder bus(line);
  bus.add(broadcast, 0).add(request, 20 * kMs).add(response, 3 * kMs);
  bus.add(glitch, 20 * kMs).add(fragment, 1200 * kUs).add(request, 20 * kMs);
  const auto records = frame(bus.per_byte(), line, kUs);
  ASSERT_EQ(records.size(), 6U);
  EXPECT_EQ(records[3].kind, RecordKind::kNoise);
  EXPECT_EQ(bytes_of(records[3]), glitch);
  EXPECT_EQ(records[4].kind, RecordKind::kFrame);
  EXPECT_EQ(bytes_of(records[4]), fragment);
  EXPECT_FALSE(records[4].crc_ok);
  EXPECT_TRUE(records[5].crc_ok);
}

TEST(SickBusFraming, DamagedFrameOfNoLengthRuleThenNoiseAfterMoreThanT15AreTwoRecords) {
  // Diagnostics, return query data (FC08/0000): its length is the master's choice.
  auto damaged = with_crc({0x05, 0x08, 0x00, 0x00, 0x12, 0x34, 0x56});
  damaged[5] ^= 0x10U;
  const std::vector<std::uint8_t> burst = {0xA5, 0x5A, 0x3C};
  const auto records = around_a_t15_pause(damaged, burst);
  ASSERT_EQ(records.size(), 5U);
  EXPECT_EQ(records[2].kind, RecordKind::kFrame);
  EXPECT_EQ(bytes_of(records[2]), damaged);
  EXPECT_FALSE(records[2].crc_ok);
  EXPECT_EQ(records[3].kind, RecordKind::kNoise);
  EXPECT_EQ(bytes_of(records[3]), burst);
  EXPECT_TRUE(records[4].crc_ok);
}

// A slow sender's pause inside its frame, the frame then damaged: its length rule goes on
// past the pause, so the bytes after it are still the frame's.
TEST(SickBusFraming, DamagedFrameWhoseLengthGoesOnPastAPauseStaysOneFrame) {
  LineSettings line;
  line.baud = 19200;
  const auto request = with_crc({0x05, 0x03, 0x00, 0x00, 0x00, 0x02});
  auto response = with_crc({0x05, 0x03, 0x04, 0x01, 0x02, 0x03, 0x04});
  response[6] ^= 0x01U;
  const std::vector<std::uint8_t> head(response.begin(), response.begin() + 4);
  const std::vector<std::uint8_t> tail(response.begin() + 4, response.end());
  BusBuilder bus(line);
  bus.add(request, 0).add(head, 5 * kMs).add(tail, 1200 * kUs).add(request, 20 * kMs);
  const auto records = frame(bus.per_byte(), line, kUs);
  ASSERT_EQ(records.size(), 3U);
  EXPECT_EQ(bytes_of(records[1]), response);
  EXPECT_FALSE(records[1].crc_ok);
  EXPECT_TRUE(records[1].issues.has(IssueId::kT15));
}

// Through an adapter that hides the gaps, a flipped bit turned a request's function code
// into one whose rule is shorter (03 -> 0B, 4 bytes). Cut there, its last four bytes would
// read as the start of a broadcast whose rule asks for more: two broken records where one
// was sent. It stays one damaged frame.
TEST(SickBusFraming, DamagedFunctionCodeDoesNotCutAFrameIntoTwoBrokenOnes) {
  const PolledSlave polled;
  const auto broadcast = with_crc({0x00, 0x06, 0x00, 0x01, 0x00, 0x02});
  auto damaged = polled.request;
  damaged[1] = 0x0B;
  BusBuilder bus(polled.line);
  bus.add(broadcast, 0).add(polled.request, 60 * kMs).add(polled.response, 3 * kMs);
  bus.add(damaged, 60 * kMs).add(polled.request, 60 * kMs).add(polled.response, 3 * kMs);
  const auto records = frame(bus.batched(16 * kMs), polled.line, 16 * kMs);
  ASSERT_EQ(records.size(), 6U);
  EXPECT_EQ(bytes_of(records[3]), damaged);
  EXPECT_FALSE(records[3].crc_ok);
  EXPECT_EQ(bytes_of(records[4]), polled.request);
  EXPECT_TRUE(records[4].crc_ok);
}

// The other side of that rule: what follows a damaged answer's length is the master's next
// request, which read as the answer still awaited would ask for 89 bytes. As a request it is
// whole, so the cut stands.
TEST(SickBusFraming, RequestRightAfterADamagedAnswerIsCutFromIt) {
  const PolledSlave polled;
  auto damaged = polled.response;
  damaged[3] ^= 0x20U;
  const auto next = with_crc({0x05, 0x03, 0x54, 0x50, 0x00, 0x01});
  BusBuilder bus(polled.line);
  bus.add(polled.request, 0).add(polled.response, 3 * kMs);
  bus.add(polled.request, 60 * kMs).add(damaged, 3 * kMs).add(next, 3 * kMs);
  bus.add(polled.response, 3 * kMs).add(polled.request, 60 * kMs);
  const auto records = frame(bus.batched(16 * kMs), polled.line, 16 * kMs);
  ASSERT_EQ(records.size(), 7U);
  EXPECT_EQ(bytes_of(records[3]), damaged);
  EXPECT_EQ(bytes_of(records[4]), next);
  EXPECT_TRUE(records[4].crc_ok);
}

// Diagnostics, return query data (FC08/0000) from slave 5: a frame of no length rule, whose
// end only its CRC shows. With `crc_high_zero`, data whose CRC's last byte is 00.
std::vector<std::uint8_t> echo_request(bool crc_high_zero) {
  for (unsigned data = 0;; ++data) {
    auto frame = with_crc({0x05, 0x08, 0x00, 0x00, static_cast<std::uint8_t>(data >> 8U),
                           static_cast<std::uint8_t>(data)});
    if ((frame.back() == 0x00) == crc_high_zero) return frame;
  }
}

// Appending 00 keeps a Modbus CRC valid, so a frame of no length rule followed by a 00
// turnaround byte and then a silence holds its CRC both without and with that byte. Where
// the timestamps show a pause before the 00 (96 us at 115200 baud, a character), the frame
// ends before it.
TEST(SickBusFraming, ZeroByteAfterAPauseBeforeASilenceIsTheSendersTurnaround) {
  LineSettings line{115200};
  const auto request = echo_request(false);
  const std::vector<std::uint8_t> glitch = {0x00};
  BusBuilder bus(line);
  bus.add(request, 0).add(glitch, 96 * kUs).add(request, 10 * kMs).add(request, 50 * kMs);
  const auto records = frame(bus.per_byte(), line, kUs);
  ASSERT_EQ(records.size(), 4U);
  EXPECT_EQ(bytes_of(records[0]), request);
  EXPECT_EQ(records[1].kind, RecordKind::kNoise);
  EXPECT_EQ(bytes_of(records[1]), glitch);
  EXPECT_EQ(bytes_of(records[2]), request);
}

// A frame whose CRC ends in 00, its bytes back to back, before a silence: the 00 is its own.
TEST(SickBusFraming, CrcEndingInZeroSentBackToBackStaysWhole) {
  LineSettings line{115200};
  const auto request = echo_request(true);
  BusBuilder bus(line);
  bus.add(request, 0).add(request, 10 * kMs).add(request, 50 * kMs);
  const auto records = frame(bus.per_byte(), line, kUs);
  ASSERT_EQ(records.size(), 3U);
  for (const Record& r : records) {
    EXPECT_EQ(bytes_of(r), request);
    EXPECT_TRUE(r.crc_ok);
  }
}

// Two ports (the directions of a link): a response that starts before its request's last
// byte was read on the other port is still two frames, paired.
TEST(SickBusFraming, TwoPortsAreFramedApartAndMergedByTime) {
  LineSettings line;
  line.baud = 9600;
  const auto request = with_crc({0x02, 0x03, 0x00, 0x00, 0x00, 0x01});
  const auto response = with_crc({0x02, 0x03, 0x02, 0xAB, 0xCD});
  const Nanos ct = line.char_time();
  std::vector<Chunk> chunks;
  // Interleaved reads: port 0 carries the request byte by byte, port 1 the response,
  // which a full-duplex slave starts while the request's CRC is still on the wire.
  const Nanos t0 = kNanosPerSecond;
  for (std::size_t i = 0; i < request.size(); ++i) {
    Chunk c;
    c.t_end = t0 + static_cast<Nanos>(i + 1) * ct;
    c.bytes = std::span(request).subspan(i, 1);
    c.port = 0;
    chunks.push_back(c);
    if (i >= 6) {
      Chunk r;
      r.t_end = c.t_end + ct / 2;
      r.bytes = std::span(response).subspan(i - 6, 1);
      r.port = 1;
      chunks.push_back(r);
    }
  }
  for (std::size_t i = 2; i < response.size(); ++i) {
    Chunk r;
    r.t_end = t0 + static_cast<Nanos>(request.size() + i - 1) * ct + ct / 2;
    r.bytes = std::span(response).subspan(i, 1);
    r.port = 1;
    chunks.push_back(r);
  }
  PipelineOptions options;
  options.line = line;
  options.timing_resolution = kUs;
  CollectingSink sink;
  DecodePipeline pipeline(options, sink);
  for (const auto& c : chunks) pipeline.push(c);
  pipeline.finish();
  ASSERT_EQ(sink.records.size(), 2U);
  EXPECT_EQ(bytes_of(sink.records[0]), request);
  EXPECT_EQ(bytes_of(sink.records[1]), response);
  EXPECT_EQ(sink.records[0].role, Role::kRequest);
  EXPECT_EQ(sink.records[1].role, Role::kResponse);
  EXPECT_EQ(sink.records[0].txn, sink.records[1].txn);
  EXPECT_EQ(sink.records[0].seq, 0U);
  EXPECT_EQ(sink.records[1].seq, 1U);
}

}  // namespace
}  // namespace rtu
