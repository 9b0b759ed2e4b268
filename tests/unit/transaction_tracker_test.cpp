#include "pairing/transaction_tracker.hpp"

#include <gtest/gtest.h>

#include "bus_builder.hpp"
#include "pipeline/decode_pipeline.hpp"

namespace rtu {
namespace {

using test::BusBuilder;
using test::CollectingSink;
using test::with_crc;

constexpr Nanos kMs = kNanosPerMilli;

const auto kRead = with_crc({0x01, 0x03, 0x00, 0x32, 0x00, 0x03});
const auto kReadAnswer = with_crc({0x01, 0x03, 0x06, 0xEA, 0x60, 0xC3, 0x50, 0xDB, 0x6C});
const auto kReadSlave2 = with_crc({0x02, 0x03, 0x00, 0x00, 0x00, 0x01});
const auto kAnswerSlave2 = with_crc({0x02, 0x03, 0x02, 0x12, 0x34});

CollectingSink decode(const BusBuilder& bus, Nanos timeout = 1000 * kMs) {
  CollectingSink sink;
  PipelineOptions options;
  options.line = bus.line();
  options.response_timeout = timeout;
  options.timing_resolution = 16 * kMs;
  DecodePipeline pipeline(options, sink);
  for (const auto& c : bus.batched(16 * kMs)) pipeline.push(c);
  pipeline.finish();
  return sink;
}

TEST(TransactionTracker, PairsRequestWithResponseAndMeasuresLatency) {
  BusBuilder bus;
  bus.add(kRead, 0).add(kReadAnswer, 30 * kMs);
  const auto sink = decode(bus);
  ASSERT_EQ(sink.records.size(), 2U);
  const auto& req = sink.records[0];
  const auto& resp = sink.records[1];
  EXPECT_EQ(req.role, Role::kRequest);
  EXPECT_EQ(resp.role, Role::kResponse);
  EXPECT_EQ(req.txn, resp.txn);
  EXPECT_GE(req.txn, 0);
  // 30 ms of silence; the 16 ms batching can shift each end by less than one period.
  EXPECT_NEAR(static_cast<double>(resp.latency), 30.0 * kMs, 16.0 * kMs);
  ASSERT_EQ(sink.requests_of_responses.size(), 1U);
  EXPECT_EQ(sink.requests_of_responses[0].txn, req.txn);
}

TEST(TransactionTracker, EchoFunctionsTakeTheirRoleFromOrder) {
  const auto write = with_crc({0x01, 0x06, 0x00, 0x02, 0x00, 0x02});
  BusBuilder bus;
  bus.add(write, 0).add(write, 20 * kMs).add(write, 100 * kMs).add(write, 20 * kMs);
  const auto sink = decode(bus);
  ASSERT_EQ(sink.records.size(), 4U);
  EXPECT_EQ(sink.records[0].role, Role::kRequest);
  EXPECT_EQ(sink.records[1].role, Role::kResponse);
  EXPECT_EQ(sink.records[2].role, Role::kRequest);
  EXPECT_EQ(sink.records[3].role, Role::kResponse);
  EXPECT_EQ(sink.records[2].txn, sink.records[3].txn);
  EXPECT_NE(sink.records[0].txn, sink.records[2].txn);
}

TEST(TransactionTracker, NewRequestBeforeTheResponseIsATimeout) {
  BusBuilder bus;
  bus.add(kRead, 0).add(kReadSlave2, 200 * kMs).add(kAnswerSlave2, 20 * kMs);
  const auto sink = decode(bus);
  ASSERT_EQ(sink.records.size(), 3U);
  EXPECT_TRUE(sink.records[0].issues.has(IssueId::kTimeout));
  EXPECT_EQ(sink.records[0].txn, -1) << "unanswered requests have no transaction";
  EXPECT_EQ(sink.records[1].txn, sink.records[2].txn);
}

TEST(TransactionTracker, ResponseWithNoOpenRequestIsUnsolicited) {
  BusBuilder bus;
  bus.add(kReadAnswer, 0);
  const auto sink = decode(bus);
  ASSERT_EQ(sink.records.size(), 1U);
  EXPECT_EQ(sink.records[0].role, Role::kResponse);
  EXPECT_TRUE(sink.records[0].issues.has(IssueId::kUnsolicited));
}

// A break (a recorder stopped and started again): the request open at it leaves without a
// verdict, as at the end of a capture, and the answer after it pairs with nothing; a
// request after the break pairs as usual.
TEST(TransactionTracker, NothingPairsAcrossABreak) {
  BusBuilder before;
  before.add(kRead, 0);
  BusBuilder after;
  after.add(kReadAnswer, 0).add(kRead, 50 * kMs).add(kReadAnswer, 20 * kMs);
  CollectingSink sink;
  PipelineOptions options;
  options.line = before.line();
  options.timing_resolution = 16 * kMs;
  DecodePipeline pipeline(options, sink);
  for (const auto& c : before.batched(16 * kMs)) pipeline.push(c);
  pipeline.break_capture();
  for (auto c : after.batched(16 * kMs)) {
    c.t_end += 100 * kMs;  // within the response timeout of the request before the break
    pipeline.push(c);
  }
  pipeline.finish();
  ASSERT_EQ(sink.records.size(), 4U);
  EXPECT_EQ(sink.records[0].role, Role::kRequest);
  EXPECT_FALSE(sink.records[0].issues.has(IssueId::kTimeout));
  EXPECT_EQ(sink.records[0].txn, -1);
  EXPECT_EQ(sink.records[1].role, Role::kResponse);
  EXPECT_TRUE(sink.records[1].issues.has(IssueId::kUnsolicited));
  EXPECT_EQ(sink.records[1].txn, -1);
  EXPECT_EQ(sink.records[1].gap_before, kUnknownTime) << "no silence was observed across it";
  EXPECT_GE(sink.records[2].txn, 0);
  EXPECT_EQ(sink.records[2].txn, sink.records[3].txn);
  EXPECT_TRUE(sink.finished);
}

TEST(TransactionTracker, ResponseFromAnotherSlaveIsPairedAndFlagged) {
  BusBuilder bus;
  bus.add(kRead, 0).add(kAnswerSlave2, 20 * kMs);
  const auto sink = decode(bus);
  ASSERT_EQ(sink.records.size(), 2U);
  EXPECT_TRUE(sink.records[1].issues.has(IssueId::kWrongSlave));
  EXPECT_EQ(sink.records[0].txn, sink.records[1].txn);
}

// A late answer cannot be paired live (its request already went out when the timeout ran
// out), so it is not paired in a replay either: both flagged, no txn, latency still shown.
TEST(TransactionTracker, LateResponseIsFlaggedWithItsTimedOutRequestAndNoTxn) {
  BusBuilder bus;
  bus.add(kRead, 0).add(kReadAnswer, 300 * kMs);
  const auto sink = decode(bus, 100 * kMs);
  ASSERT_EQ(sink.records.size(), 2U);
  EXPECT_TRUE(sink.records[0].issues.has(IssueId::kTimeout));
  EXPECT_TRUE(sink.records[1].issues.has(IssueId::kLate));
  EXPECT_EQ(sink.records[0].txn, -1);
  EXPECT_EQ(sink.records[1].txn, -1);
  EXPECT_GT(sink.records[1].latency, 280 * kMs);
}

// Live calls idle() while the line is quiet. A late answer must come out the same whether
// an idle moment released its request first or not.
TEST(TransactionTracker, LateResponseIsTheSameWithOrWithoutAnIdleMomentBeforeIt) {
  BusBuilder bus;
  bus.add(kRead, 0).add(kReadAnswer, 300 * kMs).add(kReadSlave2, 50 * kMs);
  bus.add(kAnswerSlave2, 20 * kMs);
  PipelineOptions options;
  options.line = bus.line();
  options.response_timeout = 100 * kMs;
  const auto chunks = bus.per_byte();
  const auto run = [&](bool with_idle) {
    CollectingSink sink;
    DecodePipeline pipeline(options, sink);
    for (std::size_t i = 0; i < chunks.size(); ++i) {
      if (with_idle && i == kRead.size()) pipeline.idle(chunks[i - 1].t_end + 250 * kMs);
      pipeline.push(chunks[i]);
    }
    pipeline.finish();
    return sink;
  };
  const auto replayed = run(false);
  const auto lived = run(true);
  ASSERT_EQ(replayed.records.size(), 4U);
  ASSERT_EQ(lived.records.size(), 4U);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(lived.records[i].txn, replayed.records[i].txn) << i;
    EXPECT_EQ(lived.records[i].issues.bits(), replayed.records[i].issues.bits()) << i;
  }
  EXPECT_EQ(replayed.records[1].txn, -1);
  EXPECT_EQ(replayed.records[2].txn, replayed.records[3].txn);
  EXPECT_GE(replayed.records[2].txn, 0);
}

// An adapter may hold an answer's bytes back (up to its latency) after they were on the
// wire: an idle moment just after the timeout must not time out a request whose answer
// started within it, because the replay places that answer where it was on the wire.
TEST(TransactionTracker, IdleMomentWithinTheDeliveryDelayDoesNotTimeOutAnAnswerOnTheWire) {
  BusBuilder bus;
  bus.add(kRead, 0).add(kReadAnswer, 95 * kMs);
  PipelineOptions options;
  options.line = bus.line();
  options.response_timeout = 100 * kMs;
  options.timing_resolution = 16 * kMs;
  const auto chunks = bus.usb(16 * kMs, 64);
  ASSERT_EQ(chunks.size(), 2U);
  CollectingSink sink;
  DecodePipeline pipeline(options, sink);
  pipeline.push(chunks[0]);
  // Nothing read yet 101 ms after the request: the answer is still in the adapter.
  pipeline.idle(chunks[0].t_end + 101 * kMs);
  pipeline.push(chunks[1]);
  pipeline.finish();
  ASSERT_EQ(sink.records.size(), 2U);
  EXPECT_FALSE(sink.records[0].issues.has(IssueId::kTimeout));
  EXPECT_FALSE(sink.records[1].issues.has(IssueId::kLate));
  EXPECT_EQ(sink.records[0].txn, sink.records[1].txn);
  EXPECT_GE(sink.records[0].txn, 0);
}

// A live capture sleeps when an idle moment could decide nothing: that must be exactly when
// no bytes are held and no request waits for its answer or its timeout.
TEST(TransactionTracker, PipelineAwaitsIdleOnlyWhileSomethingIsUndecided) {
  BusBuilder bus;
  bus.add(kRead, 0).add(kRead, 500 * kMs).add(kReadAnswer, 20 * kMs);
  PipelineOptions options;
  options.line = bus.line();
  options.response_timeout = 100 * kMs;
  const auto chunks = bus.usb(16 * kMs, 64);
  ASSERT_EQ(chunks.size(), 3U);
  CollectingSink sink;
  DecodePipeline pipeline(options, sink);
  EXPECT_FALSE(pipeline.awaits_idle()) << "nothing read yet";
  pipeline.push(chunks[0]);
  EXPECT_TRUE(pipeline.awaits_idle()) << "the request's bytes are held";
  pipeline.idle(chunks[0].t_end + 50 * kMs);
  EXPECT_TRUE(sink.records.empty()) << "the tracker holds the request until it is decided";
  EXPECT_TRUE(pipeline.awaits_idle()) << "the request waits for its answer";
  pipeline.idle(chunks[0].t_end + 200 * kMs);
  ASSERT_EQ(sink.records.size(), 1U);
  EXPECT_TRUE(sink.records[0].issues.has(IssueId::kTimeout));
  EXPECT_FALSE(pipeline.awaits_idle()) << "timed out: nothing left to decide";
  pipeline.push(chunks[1]);
  EXPECT_TRUE(pipeline.awaits_idle()) << "the second request's bytes are held";
  pipeline.push(chunks[2]);
  pipeline.idle(chunks[2].t_end + 50 * kMs);
  ASSERT_EQ(sink.records.size(), 3U);
  EXPECT_EQ(sink.records[1].txn, sink.records[2].txn);
  EXPECT_FALSE(pipeline.awaits_idle()) << "answered: nothing left to decide";
}

// The live timer wakes up when something can first be decided: not a moment earlier
// (idle() would decide nothing) and, being exact, never later. Two cases: bytes a framer
// holds (a request cut short) and a whole request waiting for its timeout.
TEST(TransactionTracker, NextIdleDecisionIsTheFirstMomentIdleDecides) {
  BusBuilder bus;
  bus.add(kRead, 0);
  PipelineOptions options;
  options.line = bus.line();
  options.response_timeout = 1000 * kMs;
  options.timing_resolution = 16 * kMs;
  options.learn_resolution = false;  // a lone read teaches nothing about the adapter
  const auto chunks = bus.usb(16 * kMs, 64);
  ASSERT_EQ(chunks.size(), 1U);

  {  // Held bytes: the first five of the request, decided once the line stays quiet.
    CollectingSink sink;
    DecodePipeline pipeline(options, sink);
    EXPECT_EQ(pipeline.next_idle_decision(), kUnknownTime);
    Chunk cut = chunks[0];
    cut.bytes = cut.bytes.first(5);
    pipeline.push(cut);
    const Nanos due = pipeline.next_idle_decision();
    ASSERT_NE(due, kUnknownTime);
    EXPECT_GT(due, cut.t_end);
    EXPECT_LT(due, cut.t_end + 100 * kMs);
    pipeline.idle(due - 1);
    EXPECT_TRUE(sink.records.empty());
    EXPECT_EQ(pipeline.next_idle_decision(), due) << "the bytes are still held";
    pipeline.idle(due);
    EXPECT_EQ(sink.records.size(), 1U) << "decided at that moment";
  }
  {  // A whole request: decided as it is read, then held until its timeout.
    CollectingSink sink;
    DecodePipeline pipeline(options, sink);
    pipeline.push(chunks[0]);
    const Nanos due = pipeline.next_idle_decision();
    ASSERT_NE(due, kUnknownTime);
    EXPECT_GT(due, chunks[0].t_end + options.response_timeout);
    pipeline.idle(due - 1);
    EXPECT_TRUE(sink.records.empty());
    EXPECT_TRUE(pipeline.awaits_idle());
    pipeline.idle(due);
    ASSERT_EQ(sink.records.size(), 1U);
    EXPECT_TRUE(sink.records[0].issues.has(IssueId::kTimeout));
    EXPECT_EQ(pipeline.next_idle_decision(), kUnknownTime);
    EXPECT_FALSE(pipeline.awaits_idle());
  }
}

TEST(TransactionTracker, BroadcastExpectsNoResponse) {
  const auto broadcast = with_crc({0x00, 0x06, 0x00, 0x02, 0x00, 0x01});
  BusBuilder bus;
  bus.add(broadcast, 0).add(kRead, 100 * kMs).add(kReadAnswer, 20 * kMs);
  const auto sink = decode(bus);
  ASSERT_EQ(sink.records.size(), 3U);
  EXPECT_EQ(sink.records[0].role, Role::kRequest);
  EXPECT_FALSE(sink.records[0].issues.has(IssueId::kTimeout));
  EXPECT_EQ(sink.records[1].txn, sink.records[2].txn);
}

TEST(TransactionTracker, RecordsLeaveInTimeOrderWhileARequestIsHeld) {
  BusBuilder bus;
  bus.add(kRead, 0).add({0xFF, 0x00}, 5 * kMs).add(kReadAnswer, 20 * kMs);
  const auto sink = decode(bus);
  ASSERT_EQ(sink.records.size(), 3U);
  EXPECT_EQ(sink.records[1].kind, RecordKind::kNoise);
  for (std::size_t i = 1; i < sink.records.size(); ++i) {
    EXPECT_LE(sink.records[i - 1].t_end, sink.records[i].t_start);
  }
  EXPECT_EQ(sink.records[0].txn, sink.records[2].txn);
}

TEST(TransactionTracker, UnansweredRequestAtCaptureEndGetsNoVerdictBeforeTheTimeout) {
  BusBuilder bus;
  bus.add(kRead, 0);
  const auto sink = decode(bus);
  ASSERT_EQ(sink.records.size(), 1U);
  EXPECT_FALSE(sink.records[0].issues.has(IssueId::kTimeout));
  EXPECT_TRUE(sink.finished);
}

}  // namespace
}  // namespace rtu
