#include "framing/framer.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "bus_builder.hpp"

namespace rtu {
namespace {

using test::BusBuilder;
using test::CollectingSink;
using test::with_crc;

constexpr Nanos kMs = kNanosPerMilli;

const std::vector<std::uint8_t> kReadRequest = {0x01, 0x03, 0x00, 0x32, 0x00, 0x03, 0xA4, 0x04};
const std::vector<std::uint8_t> kReadResponse = {0x01, 0x03, 0x06, 0xEA, 0x60, 0xC3,
                                                 0x50, 0xDB, 0x6C, 0xD1, 0x3F};

std::vector<Record> run(const std::vector<Chunk>& chunks, const LineSettings& line,
                        Nanos resolution, bool per_byte_exact = false) {
  CollectingSink sink;
  Framer framer(FramerConfig{line, resolution, per_byte_exact}, sink);
  for (const auto& c : chunks) framer.push(c);
  framer.finish();
  return sink.records;
}

std::vector<std::uint8_t> bytes_of(const Record& r) {
  return {r.bytes().begin(), r.bytes().end()};
}

TEST(Framer, PerByteTimingSplitsRequestAndResponse) {
  BusBuilder bus;
  bus.add(kReadRequest, 0).add(kReadResponse, 10 * kMs);
  const auto records = run(bus.per_byte(), bus.line(), kNanosPerMicro);
  ASSERT_EQ(records.size(), 2U);
  EXPECT_EQ(bytes_of(records[0]), kReadRequest);
  EXPECT_EQ(bytes_of(records[1]), kReadResponse);
  EXPECT_TRUE(records[0].crc_ok);
  EXPECT_TRUE(records[1].crc_ok);
  EXPECT_TRUE(records[1].issues.empty());
  // The gap before the response is the 10 ms of silence, measured exactly.
  EXPECT_EQ(records[1].gap_before, 10 * kMs);
}

TEST(Framer, FrameTimeIsItsFirstByteCountedBackFromTheChunk) {
  BusBuilder bus;
  bus.add(kReadRequest, 0);
  const auto chunks = bus.batched(16 * kMs);
  ASSERT_EQ(chunks.size(), 1U);
  const auto records = run(chunks, bus.line(), 16 * kMs);
  ASSERT_EQ(records.size(), 1U);
  const Nanos ct = bus.line().char_time();
  EXPECT_EQ(records[0].t_end, chunks[0].t_end);
  EXPECT_EQ(records[0].t_start, chunks[0].t_end - 8 * ct);
}

TEST(Framer, UsbBatchingGluesFramesButLengthAndCrcSplitThem) {
  BusBuilder bus;
  // Slave answers 2 ms after the request: both land in one 16 ms USB transfer.
  bus.add(kReadRequest, 0).add(kReadResponse, 2 * kMs).add(kReadRequest, 5 * kMs);
  const auto chunks = bus.batched(16 * kMs);
  ASSERT_GT(chunks[0].bytes.size(), kReadRequest.size()) << "request and response glued";
  const auto records = run(chunks, bus.line(), 16 * kMs);
  ASSERT_EQ(records.size(), 3U);
  EXPECT_EQ(bytes_of(records[0]), kReadRequest);
  EXPECT_EQ(bytes_of(records[1]), kReadResponse);
  EXPECT_EQ(bytes_of(records[2]), kReadRequest);
  for (const auto& r : records) EXPECT_FALSE(r.issues.has(IssueId::kT35)) << "not observable";
}

TEST(Framer, LongFrameSplitAcrossManyChunksIsReassembled) {
  std::vector<std::uint8_t> body = {0x11, 0x03, 0xF0};
  for (int i = 0; i < 0xF0; ++i) body.push_back(static_cast<std::uint8_t>(i));
  const std::uint16_t crc = crc16(body);
  body.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  body.push_back(static_cast<std::uint8_t>(crc >> 8U));
  LineSettings line;
  line.baud = 115200;
  BusBuilder bus(line);
  bus.add(with_crc({0x11, 0x03, 0x00, 0x00, 0x00, 0x78}), 0).add(body, 3 * kMs);
  const auto records = run(bus.batched(1 * kMs), line, 1 * kMs);
  ASSERT_EQ(records.size(), 2U);
  EXPECT_EQ(records[1].size, body.size());
  EXPECT_TRUE(records[1].crc_ok);
}

TEST(Framer, NoiseBeforeAFrameBecomesANoiseRecordAndNoByteIsLost) {
  BusBuilder bus;
  bus.add({0x00, 0xFF, 0x00}, 0).add(kReadRequest, 0).add(kReadResponse, 10 * kMs);
  const auto records = run(bus.batched(16 * kMs), bus.line(), 16 * kMs);
  ASSERT_EQ(records.size(), 3U);
  EXPECT_EQ(records[0].kind, RecordKind::kNoise);
  EXPECT_EQ(bytes_of(records[0]), (std::vector<std::uint8_t>{0x00, 0xFF, 0x00}));
  EXPECT_EQ(bytes_of(records[1]), kReadRequest);
  EXPECT_EQ(bytes_of(records[2]), kReadResponse);
}

TEST(Framer, BadCrcFrameOfAKnownSlaveIsAFrameWithACrcIssue) {
  auto damaged = kReadResponse;
  damaged[4] ^= 0x01;
  BusBuilder bus;
  bus.add(kReadRequest, 0).add(kReadResponse, 10 * kMs);
  bus.add(kReadRequest, 50 * kMs).add(damaged, 10 * kMs);
  bus.add(kReadRequest, 50 * kMs).add(kReadResponse, 10 * kMs);
  const auto records = run(bus.batched(16 * kMs), bus.line(), 16 * kMs);
  ASSERT_EQ(records.size(), 6U);
  EXPECT_EQ(bytes_of(records[3]), damaged);
  EXPECT_EQ(records[3].kind, RecordKind::kFrame);
  EXPECT_FALSE(records[3].crc_ok);
  EXPECT_TRUE(records[3].issues.has(IssueId::kCrc));
  EXPECT_EQ(bytes_of(records[4]), kReadRequest);
}

TEST(Framer, TruncatedResponseIsFlaggedAndTheNextRequestStillFrames) {
  BusBuilder bus;
  bus.add(kReadRequest, 0).add(kReadResponse, 10 * kMs);
  bus.add(kReadRequest, 50 * kMs)
      .add(std::vector<std::uint8_t>(kReadResponse.begin(), kReadResponse.begin() + 6), 10 * kMs);
  bus.add(kReadRequest, 50 * kMs);
  const auto records = run(bus.per_byte(), bus.line(), kNanosPerMicro);
  ASSERT_EQ(records.size(), 5U);
  EXPECT_EQ(records[3].size, 6U);
  EXPECT_TRUE(records[3].issues.has(IssueId::kTruncated));
  EXPECT_EQ(bytes_of(records[4]), kReadRequest);
}

TEST(Framer, UnknownFunctionFramesBySilenceWhereObservable) {
  const auto vendor = with_crc({0x05, 0x41, 0x10, 0x20, 0x30});
  BusBuilder bus;
  bus.add(vendor, 0).add(kReadRequest, 20 * kMs);
  const auto records = run(bus.per_byte(), bus.line(), kNanosPerMicro);
  ASSERT_EQ(records.size(), 2U);
  EXPECT_EQ(bytes_of(records[0]), vendor);
  EXPECT_TRUE(records[0].crc_ok);
}

TEST(Framer, UnknownFunctionFramesByCrcWhenTimingIsBlurred) {
  const auto vendor = with_crc({0x05, 0x41, 0x10, 0x20, 0x30});
  BusBuilder bus;
  bus.add(vendor, 0).add(kReadRequest, 2 * kMs);
  const auto records = run(bus.batched(16 * kMs), bus.line(), 16 * kMs);
  ASSERT_EQ(records.size(), 2U);
  EXPECT_EQ(bytes_of(records[0]), vendor);
  EXPECT_EQ(bytes_of(records[1]), kReadRequest);
}

TEST(Framer, PauseInsideAFrameIsAT15IssueWhereObservable) {
  BusBuilder bus;
  bus.add(std::vector<std::uint8_t>(kReadRequest.begin(), kReadRequest.begin() + 4), 0)
      .add(std::vector<std::uint8_t>(kReadRequest.begin() + 4, kReadRequest.end()), 3 * kMs);
  const auto records = run(bus.per_byte(), bus.line(), kNanosPerMicro);
  ASSERT_EQ(records.size(), 1U);
  EXPECT_TRUE(records[0].crc_ok);
  EXPECT_TRUE(records[0].issues.has(IssueId::kT15));
}

TEST(Framer, ShortGapBetweenFramesIsAT35IssueWhereObservable) {
  BusBuilder bus;
  bus.add(kReadRequest, 0).add(kReadResponse, 1 * kMs);  // t3.5 at 9600 is 4.01 ms
  const auto records = run(bus.per_byte(), bus.line(), kNanosPerMicro);
  ASSERT_EQ(records.size(), 2U);
  EXPECT_TRUE(records[1].issues.has(IssueId::kT35));
  // The same traffic through a 16 ms USB adapter cannot show it.
  const auto blurred = run(bus.batched(16 * kMs), bus.line(), 16 * kMs);
  ASSERT_EQ(blurred.size(), 2U);
  EXPECT_FALSE(blurred[1].issues.has(IssueId::kT35));
}

TEST(Framer, ExceptionResponseIsFiveBytes) {
  const auto request = with_crc({0x01, 0x03, 0x00, 0x3C, 0x00, 0x01});
  const std::vector<std::uint8_t> exception = {0x01, 0x83, 0x03, 0x01, 0x31};
  BusBuilder bus;
  bus.add(request, 0).add(exception, 2 * kMs).add(kReadRequest, 3 * kMs);
  const auto records = run(bus.batched(16 * kMs), bus.line(), 16 * kMs);
  ASSERT_EQ(records.size(), 3U);
  EXPECT_EQ(bytes_of(records[1]), exception);
  EXPECT_TRUE(records[1].crc_ok);
}

TEST(Framer, EveryByteEndsUpInExactlyOneRecordWhateverTheInput) {
  // Deterministic pseudo-random bytes with valid frames sprinkled in.
  BusBuilder bus;
  std::uint32_t state = 12345;
  auto next = [&] {
    state = state * 1103515245U + 12345U;
    return static_cast<std::uint8_t>(state >> 16U);
  };
  for (int i = 0; i < 200; ++i) {
    std::vector<std::uint8_t> junk(next() % 7U);
    for (auto& b : junk) b = next();
    bus.add(junk, 0).add(kReadRequest, 1 * kMs).add(kReadResponse, 1 * kMs);
  }
  for (const Nanos period : {Nanos{1}, 1 * kMs, 16 * kMs}) {
    const auto chunks = period == 1 ? bus.per_byte() : bus.batched(period);
    const auto records = run(chunks, bus.line(), period == 1 ? kNanosPerMicro : period);
    std::size_t total = 0;
    std::size_t good = 0;
    for (const auto& r : records) {
      total += r.size;
      good += r.crc_ok ? 1 : 0;
      EXPECT_LE(r.size, kMaxAdu);
    }
    EXPECT_EQ(total, bus.size()) << "period " << period;
    EXPECT_GE(good, 400U) << "period " << period;
  }
}

}  // namespace
}  // namespace rtu

namespace rtu {
namespace {

TEST(FramerResync, VendorFunctionsPolledBackToBackThroughUsbStillFrame) {
  const auto vendor_request = with_crc({0x11, 0x41, 0xEB, 0x61});
  const auto vendor_answer = with_crc({0x11, 0x41, 0x0E, 0x0A, 0x51});
  BusBuilder bus;
  bus.add(vendor_request, 0).add(vendor_answer, 2 * kMs).add(kReadRequest, 3 * kMs);
  const auto records = run(bus.batched(16 * kMs), bus.line(), 16 * kMs);
  ASSERT_EQ(records.size(), 3U);
  EXPECT_EQ(bytes_of(records[0]), vendor_request);
  EXPECT_EQ(bytes_of(records[1]), vendor_answer);
}

// Slave 7 polled `count / 2` times with vendor function code 0x41 (no length rule): 4-byte
// requests `before_request` after the answer before, answers of 6-35 bytes `before_answer`
// after their request. Returns the frames as sent.
std::vector<std::vector<std::uint8_t>> add_vendor_polls(BusBuilder& bus, std::size_t count,
                                                        Nanos before_request, Nanos before_answer) {
  std::vector<std::vector<std::uint8_t>> sent;
  for (std::size_t n = 0; n < count; ++n) {
    std::vector<std::uint8_t> body = {0x07, 0x41};
    const std::size_t data = n % 2 == 0 ? 4 : 6 + (n * 7) % 30;  // a request, then its answer
    for (std::size_t i = 0; i < data; ++i) body.push_back(static_cast<std::uint8_t>(n * 31 + i));
    sent.push_back(with_crc(body));
    bus.add(sent.back(), n % 2 == 0 ? before_request : before_answer);
  }
  return sent;
}

void expect_each_frame_whole(const std::vector<Record>& records,
                             const std::vector<std::vector<std::uint8_t>>& sent) {
  ASSERT_EQ(records.size(), sent.size());
  for (std::size_t i = 0; i < sent.size(); ++i) {
    EXPECT_EQ(records[i].kind, RecordKind::kFrame) << i;
    EXPECT_EQ(bytes_of(records[i]), sent[i]) << i;
    EXPECT_TRUE(records[i].crc_ok) << i;
  }
}

// Adapters that deliver when the line goes idle (CH340, CP210x, PL2303) hand over a frame a
// read at a time, and reads that follow one another that closely look like a slow adapter's
// batches: the capture's resolution is then about the time from one frame to the next, and no
// silence is observable. Frames with no length rule then have only their reads to end them:
// a bus polled with a vendor function code decoded to nothing but noise.
TEST(FramerResync, VendorFunctionsReadAFrameAtATimeEndWhereTheirReadsEnd) {
  BusBuilder bus;
  auto sent = add_vendor_polls(bus, 30, 20 * kMs, 3 * kMs);
  // A CRC ending in 00 holds without that byte too: the read still ends the frame.
  const std::vector<std::uint8_t> crc_ends_in_00 = {0x07, 0x41, 0x00, 0x10, 0x00, 0x88, 0x3C, 0x00};
  ASSERT_EQ(crc_ends_in_00, with_crc({0x07, 0x41, 0x00, 0x10, 0x00, 0x88}));
  sent.push_back(crc_ends_in_00);
  bus.add(crc_ends_in_00, 20 * kMs);
  sent.push_back(with_crc({0x07, 0x41, 0x0E, 0x0A, 0x51, 0x77}));
  bus.add(sent.back(), 3 * kMs);
  const auto records = run(bus.per_add(), bus.line(), 27 * kMs);
  expect_each_frame_whole(records, sent);
}

// A bus polled with a vendor function code closer than t3.5 (a slave that answers after two
// characters), behind an adapter whose 16 ms batches hide every silence and cut the frames
// anywhere: no silence, no length rule and no read's end delimits a frame. A CRC zero
// followed by two more, back to back, still does: such a chain is no chance. Before, such a
// bus came out mostly as noise (here 30 records for 40 frames).
TEST(FramerResync, VendorFramesWithEverySilenceHiddenEndWhereThreeCrcZerosFollowInARow) {
  BusBuilder bus;
  const auto sent = add_vendor_polls(bus, 40, 3 * kMs, 2 * kMs);
  const auto records = run(bus.batched(16 * kMs), bus.line(), 16 * kMs);
  expect_each_frame_whole(records, sent);
}

// Frames of `sent` that come out of `records` whole, and CRC-valid records that were never
// sent (a span from a start inside damaged bytes whose CRC came out zero by chance).
struct Outcome {
  std::size_t whole = 0;
  std::size_t invented = 0;
  std::size_t sent = 0;
};
Outcome score(const std::vector<Record>& records,
              const std::vector<std::vector<std::uint8_t>>& sent) {
  Outcome out;
  for (const Record& r : records) {
    if (r.kind != RecordKind::kFrame || !r.crc_ok) continue;
    const bool was_sent = std::find(sent.begin(), sent.end(), bytes_of(r)) != sent.end();
    ++(was_sent ? out.whole : out.invented);
  }
  return out;
}

// A damaged vendor frame (its CRC fails) whose bytes from the second on, followed by
// the first two of `after`, come out CRC-valid; empty if no choice of two of its bytes does.
std::vector<std::uint8_t> damaged_frame_chaining_into(
    const std::vector<std::vector<std::uint8_t>>& after) {
  std::vector<std::uint8_t> damaged = {0x07, 0x41, 0x5A, 0x00, 0x00, 0x3C, 0x99};
  for (unsigned x = 0; x < 0x10000; ++x) {
    damaged[3] = static_cast<std::uint8_t>(x & 0xFFU);
    damaged[4] = static_cast<std::uint8_t>(x >> 8U);
    std::vector<std::uint8_t> span(damaged.begin() + 1, damaged.end());
    for (std::size_t k = 0; k < 2; ++k) span.insert(span.end(), after[k].begin(), after[k].end());
    if (crc16(span) == 0 && crc16(damaged) != 0) return damaged;
  }
  return {};
}

// Ten vendor polls, a damaged frame from damaged_frame_chaining_into(), and `after_count`
// more polls, the third of which comes `third_gap` after the second; read through an
// adapter that holds bytes for 16 ms. How many frames sent came whole, and how many
// CRC-valid frames were never sent.
Outcome decode_with_chaining_damage(std::size_t after_count, Nanos third_gap) {
  BusBuilder bus;
  auto sent = add_vendor_polls(bus, 10, 3 * kMs, 2 * kMs);
  std::vector<std::vector<std::uint8_t>> after;
  {
    BusBuilder rest;
    after = add_vendor_polls(rest, after_count, 3 * kMs, 2 * kMs);
  }
  const auto damaged = damaged_frame_chaining_into(after);
  if (damaged.empty()) return {};
  bus.add(damaged, 3 * kMs);
  for (std::size_t k = 0; k < after.size(); ++k) {
    bus.add(after[k], k == 2 ? third_gap : (k % 2 == 0 ? 2 * kMs : 3 * kMs));
  }
  sent.insert(sent.end(), after.begin(), after.end());
  Outcome outcome = score(run(bus.batched(16 * kMs), bus.line(), 16 * kMs), sent);
  outcome.sent = sent.size();
  return outcome;
}

// The search for the next frame after a damaged one tries a start at each of its bytes, and
// from one of them the CRC may come out zero exactly where a real frame ends: behind an
// adapter that hides every silence, real frames follow and confirm it. Such a span holds
// real frames back to back; it is none. Here the damaged frame's bytes are chosen so that
// the CRC from its second byte comes out zero at the end of the second real frame after it.
TEST(FramerResync, ASpanFromInsideADamagedFrameThatHoldsRealFramesIsNoFrame) {
  const Outcome outcome = decode_with_chaining_damage(12, 2 * kMs);
  ASSERT_GT(outcome.sent, 0U);
  EXPECT_EQ(outcome.invented, 0U);
  EXPECT_EQ(outcome.whole, outcome.sent);
}

// The same where a silence, not a further frame, follows the real frames that the span
// swallows (80 ms, which the reads show where the adapter holds bytes for 16): the silence
// confirms a span as a frame's end, and one that holds real frames back to back is none
// either.
TEST(FramerResync, ASpanThatHoldsRealFramesIsNoFrameWhenASilenceFollowsIt) {
  const Outcome outcome = decode_with_chaining_damage(8, 80 * kMs);
  ASSERT_GT(outcome.sent, 0U);
  EXPECT_EQ(outcome.invented, 0U);
  EXPECT_EQ(outcome.whole, outcome.sent);
}

// Polls of `registers` holding registers on a bus polled faster than an adapter's idle wait:
// four, then (where `noise` is not empty) a fifth whose answer comes 3 ms after a burst of
// `noise` 5 ms after its request, then a request 5 ms after the last answer, before an idle
// wait of eight character times runs out. Returns the frames sent.
std::vector<std::vector<std::uint8_t>> add_polls_with_a_held_rest(
    BusBuilder& bus, std::uint8_t registers, const std::vector<std::uint8_t>& noise) {
  const auto request = with_crc({0x01, 0x03, 0x00, 0x00, 0x00, registers});
  std::vector<std::uint8_t> body = {0x01, 0x03, static_cast<std::uint8_t>(2 * registers)};
  for (unsigned i = 0; i < 2U * registers; ++i) {
    body.push_back(static_cast<std::uint8_t>(i * 37 + 11));
  }
  const auto answer = with_crc(body);
  std::vector<std::vector<std::uint8_t>> sent;
  for (int poll = 0; poll < 4; ++poll) {
    bus.add(request, 40 * kMs).add(answer, 15 * kMs);
    sent.push_back(request);
    sent.push_back(answer);
  }
  if (!noise.empty()) {
    bus.add(request, 40 * kMs).add(noise, 5 * kMs).add(answer, 3 * kMs);
    sent.push_back(request);
    sent.push_back(answer);
  }
  bus.add(request, 5 * kMs);
  sent.push_back(request);
  return sent;
}

// An adapter that sends when the line has been idle for eight character times, or when 32
// bytes wait, on a bus polled faster than that: the last bytes of a 69-byte answer, after
// two full packets, wait until the line goes idle after the master's next request, about
// 29 ms after the answer's last full packet. A full packet shows that the adapter did not
// send because the line went idle, so the framer waits twice its delivery allowance (20 ms
// here) for the rest of a frame whose length it knows: the answer comes whole.
TEST(FramerDelivery, TheRestOfAFrameAfterFullPacketsWaitsForTheNextIdleLine) {
  LineSettings line;
  line.baud = 9600;
  BusBuilder bus(line);
  const auto sent = add_polls_with_a_held_rest(bus, 0x20, {});
  const auto reads = bus.idle_flush(8 * line.char_time(), 32);
  const Outcome outcome = score(run(reads, line, 10 * kMs), sent);
  EXPECT_EQ(outcome.invented, 0U);
  EXPECT_EQ(outcome.whole, sent.size());
  // The last answer's rest came in one read with the request after it, long after the
  // answer's full packets: more than t3.5 and the allowance once, less than twice.
  ASSERT_GE(reads.size(), 2U);
  const Chunk& rest = reads.back();
  EXPECT_EQ(rest.bytes.size(), 5U + sent.back().size());
  const Nanos held = rest.t_end - reads[reads.size() - 2].t_end;
  EXPECT_GT(held, line.t3_5() + 20 * kMs);
  EXPECT_LT(held, line.t3_5() + 40 * kMs);
}

// A poll whose answer comes 3 ms after a burst of `noise`, where the answer's rest is held
// behind its full packets as above: the answer comes whole and the noise stays noise.
void expect_the_answer_after_noise_to_wait_for_its_rest(const std::vector<std::uint8_t>& noise) {
  LineSettings line;
  line.baud = 9600;
  BusBuilder bus(line);
  const auto sent = add_polls_with_a_held_rest(bus, 24, noise);
  const auto reads = bus.idle_flush(8 * line.char_time(), 32);
  const auto records = run(reads, line, 10 * kMs);
  const Outcome outcome = score(records, sent);
  EXPECT_EQ(outcome.invented, 0U);
  EXPECT_EQ(outcome.whole, sent.size());
  const bool noise_alone = std::any_of(records.begin(), records.end(), [&](const Record& r) {
    return r.kind == RecordKind::kNoise && bytes_of(r) == noise;
  });
  EXPECT_TRUE(noise_alone);
  ASSERT_GE(reads.size(), 3U);
  EXPECT_EQ(reads[reads.size() - 2].bytes.size(), 32U);  // the answer's full packets
  EXPECT_EQ(reads[reads.size() - 3].bytes.size(), 32U);
  const Nanos held = reads.back().t_end - reads[reads.size() - 2].t_end;
  EXPECT_GT(held, line.t3_5() + 20 * kMs);
  EXPECT_LT(held, line.t3_5() + 40 * kMs);
}

// Noise of no length rule (53 bytes): the head after the request is that noise, which no
// CRC zero ends yet, and it too waits for the rest.
TEST(FramerDelivery, NoiseBeforeAnAnswerWhoseRestIsHeldWaitsForTheRestToo) {
  expect_the_answer_after_noise_to_wait_for_its_rest({0x60, 0x48, 0x4F, 0x92, 0x69, 0xFB, 0x29});
}

// Noise that reads as a whole exception answer (slave 0x46, function 0xF1: 5 bytes, CRC
// bad): the head awaits nothing, but the awaited answer after it still awaits its rest.
TEST(FramerDelivery, NoiseOfAWholeLengthBeforeAnAnswerWhoseRestIsHeldWaitsForTheRestToo) {
  expect_the_answer_after_noise_to_wait_for_its_rest({0x46, 0xF1, 0x32, 0x14, 0xE7, 0x93, 0x8E});
}

// Noise whose bytes read as a long frame's byte count (here FC 0x14 announcing 190 bytes)
// keeps the head waiting for them. Where the timestamps show no silence (an adapter that
// delivers a read when the line goes idle, slower than the frames come), whole frames then
// come inside the bytes it waits for, until a silence that shows cuts it short. Those frames
// are frames: before, the noise and every frame up to that silence were one noise record.
TEST(FramerResync, FramesInsideWhatANoiseHeadWaitedForAreFramesWhenASilenceCutsItShort) {
  const std::vector<std::uint8_t> noise = {0x35, 0x14, 0xBE, 0x1B, 0x25, 0xAB,
                                           0x59, 0xDF, 0xAC, 0xA2, 0x24};
  const auto request = with_crc({0x01, 0x03, 0x00, 0x42, 0x00, 0x02});
  const auto answer = with_crc({0x01, 0x03, 0x04, 0x12, 0x34, 0x56, 0x78});
  LineSettings line;
  line.baud = 115200;
  BusBuilder bus(line);
  bus.add(kReadRequest, 0).add(kReadResponse, 3 * kMs);
  bus.add(noise, 9 * kMs).add(kReadRequest, 2 * kMs).add(kReadResponse, 9 * kMs);
  bus.add(request, 6 * kMs).add(answer, 17 * kMs);
  const auto records = run(bus.per_add(), line, 10 * kMs);
  ASSERT_EQ(records.size(), 7U);
  EXPECT_EQ(records[2].kind, RecordKind::kNoise);
  EXPECT_EQ(bytes_of(records[2]), noise);
  const std::vector<std::vector<std::uint8_t>> frames_after = {kReadRequest, kReadResponse, request,
                                                               answer};
  for (std::size_t i = 0; i < frames_after.size(); ++i) {
    EXPECT_EQ(records[3 + i].kind, RecordKind::kFrame) << i;
    EXPECT_EQ(bytes_of(records[3 + i]), frames_after[i]) << i;
    EXPECT_TRUE(records[3 + i].crc_ok) << i;
  }
}

// The reads' ends are the weakest evidence: where a read ends exactly on a CRC zero but what
// follows confirms a longer frame (a CRC whose last byte is 00 holds without that byte too),
// the longer frame wins.
TEST(FramerResync, AReadEndingOnACrcZeroYieldsToALongerFrameThatWhatFollowsConfirms) {
  const std::vector<std::uint8_t> echo = {0x11, 0x08, 0x00, 0x00, 0x00, 0xDA, 0x63, 0x00};
  ASSERT_EQ(echo, with_crc({0x11, 0x08, 0x00, 0x00, 0x00, 0xDA}));
  std::vector<std::uint8_t> rest = {0x00};
  rest.insert(rest.end(), kReadRequest.begin(), kReadRequest.end());
  BusBuilder bus;
  bus.add({echo.begin(), echo.end() - 1}, 0).add(rest, 0).add(kReadResponse, 3 * kMs);
  const auto records = run(bus.per_add(), bus.line(), 27 * kMs);
  ASSERT_EQ(records.size(), 3U);
  EXPECT_EQ(bytes_of(records[0]), echo);
  EXPECT_EQ(bytes_of(records[1]), kReadRequest);
  EXPECT_EQ(bytes_of(records[2]), kReadResponse);
}

// Pushes each frame in two reads, the second `gap` later than the line allows, then 50 ms
// of quiet: a frame that an adapter's late delivery cut in two.
class CutFrames {
 public:
  CutFrames(Framer& framer, const LineSettings& line, Nanos gap)
      : framer_(framer), ct_(line.char_time()), gap_(gap) {}
  void send(const std::vector<std::uint8_t>& frame) {
    const std::size_t half = frame.size() / 2;
    Chunk first;
    first.bytes = std::span(frame).first(half);
    first.t_end = t_ + static_cast<Nanos>(half) * ct_;
    first.origin = origin_++;
    Chunk second;
    second.bytes = std::span(frame).subspan(half);
    second.t_end = first.t_end + gap_ + static_cast<Nanos>(frame.size() - half) * ct_;
    second.origin = origin_++;
    framer_.advance(first.t_end - 1);
    framer_.push(first);
    framer_.push(second);
    t_ = second.t_end + 50 * kMs;
    framer_.advance(t_);
  }

 private:
  Framer& framer_;
  Nanos ct_;
  Nanos gap_;
  Nanos t_ = 100 * kMs;
  std::uint64_t origin_ = 1;
};

// A CRC-valid frame cut by a read boundary with a gap shows how late the adapter delivered,
// but only a frame whose length its function code foretells says so: a frame with no length
// rule may be a chance CRC zero over several frames, whose silences, learned as delays,
// hid the silences that end such frames for the rest of the capture.
TEST(FramerResync, OnlyAFrameOfAForetoldLengthTeachesTheResolution) {
  const LineSettings line;
  const Nanos gap = 2 * kMs;  // above the resolution, below t3.5 beyond it: no silence
  ASSERT_LT(gap, line.t3_5() + kMs);
  const auto vendor = with_crc({0x07, 0x41, 1, 2, 3, 4, 5, 6, 7, 8});
  CollectingSink sink;
  Framer framer(FramerConfig{line, kMs}, sink);
  CutFrames cut(framer, line, gap);
  cut.send(vendor);
  ASSERT_EQ(sink.records.size(), 1U);
  EXPECT_EQ(bytes_of(sink.records[0]), vendor);
  EXPECT_EQ(framer.resolution(), kMs);
  cut.send(kReadRequest);
  cut.send(kReadResponse);
  ASSERT_EQ(sink.records.size(), 3U);
  EXPECT_EQ(bytes_of(sink.records[2]), kReadResponse);
  EXPECT_EQ(framer.resolution(), gap);
}

// Nor does the first frame of a slave: a chance CRC zero over the last byte of one frame and
// the first few of the next (slave 1, function 07, a CRC) fits a length rule, and the
// silence between the frames inside it taught a resolution that hid the silences ending the
// frames of a bus of vendor function codes through a 1 ms adapter, for half its capture.
TEST(FramerResync, TheFirstFrameOfASlaveTeachesNoResolution) {
  const LineSettings line;
  const Nanos gap = 2 * kMs;  // above the resolution, below t3.5 beyond it: no silence
  CollectingSink sink;
  Framer framer(FramerConfig{line, kMs}, sink);
  CutFrames cut(framer, line, gap);
  const auto request = with_crc({0x09, 0x03, 0x00, 0x00, 0x00, 0x01});
  const auto response = with_crc({0x09, 0x03, 0x02, 0x00, 0x07});
  cut.send(request);
  ASSERT_EQ(sink.records.size(), 1U);
  EXPECT_EQ(bytes_of(sink.records[0]), request);
  EXPECT_EQ(framer.resolution(), kMs);
  cut.send(response);
  ASSERT_EQ(sink.records.size(), 2U);
  EXPECT_EQ(bytes_of(sink.records[1]), response);
  EXPECT_EQ(framer.resolution(), gap);
}

TEST(FramerResync, DiagnosticEchoWithTruncatedAnswerSplitsAtTheCrcValidPrefix) {
  const auto echo = with_crc({0x11, 0x08, 0x00, 0x00, 0x5D, 0x28, 0xEB, 0x34, 0x59, 0x43});
  const std::vector<std::uint8_t> truncated(echo.begin(), echo.begin() + 8);
  BusBuilder bus;
  bus.add(kReadRequest, 0).add(kReadResponse, 2 * kMs);  // slave 1 is known to the bus
  bus.add(with_crc({0x11, 0x03, 0x00, 0x00, 0x00, 0x01}), 3 * kMs)
      .add(with_crc({0x11, 0x03, 0x02, 0x00, 0x07}), 2 * kMs);  // so is slave 0x11
  bus.add(echo, 3 * kMs).add(truncated, 2 * kMs).add(kReadRequest, 3 * kMs);
  const auto records = run(bus.batched(16 * kMs), bus.line(), 16 * kMs);
  ASSERT_EQ(records.size(), 7U);
  EXPECT_EQ(bytes_of(records[4]), echo);
  EXPECT_TRUE(records[4].crc_ok);
  EXPECT_EQ(bytes_of(records[5]), truncated);
  EXPECT_FALSE(records[5].crc_ok);
  EXPECT_EQ(bytes_of(records[6]), kReadRequest);
}

TEST(FramerResync, UnaskedResponseShapedBytesWithBadCrcAreNoise) {
  BusBuilder bus;
  bus.add(kReadRequest, 0).add(kReadResponse, 10 * kMs);
  bus.add({0x01, 0x87, 0x32, 0x3A, 0x6A}, 20 * kMs).add(kReadRequest, 20 * kMs);
  const auto records = run(bus.per_byte(), bus.line(), kNanosPerMicro);
  ASSERT_EQ(records.size(), 4U);
  EXPECT_EQ(records[2].kind, RecordKind::kNoise);
  EXPECT_EQ(bytes_of(records[3]), kReadRequest);
}

TEST(FramerResync, ThreeByteFragmentOfTheAwaitedAnswerIsATruncatedFrame) {
  BusBuilder bus;
  bus.add(kReadRequest, 0).add({0x01, 0x03, 0x06}, 10 * kMs).add(kReadRequest, 30 * kMs);
  const auto records = run(bus.batched(16 * kMs), bus.line(), 16 * kMs);
  ASSERT_EQ(records.size(), 3U);
  EXPECT_EQ(records[1].kind, RecordKind::kFrame);
  EXPECT_TRUE(records[1].issues.has(IssueId::kTruncated));
}

// A reader that fell behind (a busy or starved host) takes many queued bytes in one read,
// long after the quiet that decides a frame would have passed since the byte before them,
// had the line been quiet. It was not: the read's own bytes filled that time. At 9600 baud
// a 205-byte answer whose last 142 bytes come in one such read is still one frame.
TEST(Framer, AReadOfLongQueuedBytesGoesOnWithTheFrameBeforeIt) {
  LineSettings line;
  line.baud = 9600;
  BusBuilder bus(line);
  const std::vector<std::uint8_t> request = with_crc({0x11, 0x03, 0x00, 0x00, 0x00, 0x64});
  std::vector<std::uint8_t> body = {0x11, 0x03, 200};
  for (int i = 0; i < 200; ++i) body.push_back(static_cast<std::uint8_t>(i * 7));
  std::vector<std::uint8_t> response = body;
  const std::uint16_t crc = crc16(response);
  response.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  response.push_back(static_cast<std::uint8_t>(crc >> 8U));
  ASSERT_EQ(crc16(response), 0);
  bus.add(request, 0).add(response, 2 * kMs);
  std::vector<Chunk> reads = bus.per_byte();
  const std::size_t held = 142;
  Chunk late = reads[reads.size() - held];
  late.bytes = {late.bytes.data(), held};
  late.t_end = reads.back().t_end;
  reads.resize(reads.size() - held);
  reads.push_back(late);
  // Unmarked; marked late with no moment the port was seen empty; and marked with the one
  // a live run has (when the read before was issued).
  const Nanos issued = reads[reads.size() - 2].t_end;
  for (const auto& [marked, quiet_until] :
       {std::pair{false, kUnknownTime}, std::pair{true, kUnknownTime}, std::pair{true, issued}}) {
    reads.back().read_late = marked;
    reads.back().quiet_until = quiet_until;
    const auto records = run(reads, bus.line(), kMs);
    ASSERT_EQ(records.size(), 2U) << "marked " << marked << " quiet until " << quiet_until;
    EXPECT_EQ(bytes_of(records[1]), response);
    EXPECT_TRUE(records[1].crc_ok);
  }
}

}  // namespace
}  // namespace rtu
