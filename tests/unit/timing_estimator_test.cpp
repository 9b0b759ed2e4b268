// The timing resolution a capture really has, estimated from its reads: the delivery period
// of a batching adapter while traffic flows, never the pauses between bursts of polling.
#include "framing/timing_estimator.hpp"

#include <gtest/gtest.h>

#include "bus_builder.hpp"

namespace rtu {
namespace {

using test::BusBuilder;
using test::with_crc;

constexpr Nanos kMs = kNanosPerMilli;

TimingEstimator estimate(const std::vector<Chunk>& chunks) {
  TimingEstimator estimator;
  for (const auto& c : chunks) estimator.add(c);
  return estimator;
}

TEST(TimingEstimator, PerByteReadsShowTheTimestampPrecision) {
  BusBuilder bus;
  for (int i = 0; i < 20; ++i) bus.add(with_crc({0x01, 0x03, 0x00, 0x00, 0x00, 0x01}), 50 * kMs);
  const auto estimator = estimate(bus.per_byte());
  EXPECT_TRUE(estimator.mostly_single_bytes());
  EXPECT_EQ(estimator.resolution(kNanosPerMicro), kNanosPerMicro);
}

TEST(TimingEstimator, BatchedReadsShowTheAdaptersPeriod) {
  BusBuilder bus;
  for (int i = 0; i < 50; ++i) bus.add(with_crc({0x01, 0x03, 0x00, 0x00, 0x00, 0x20}), 3 * kMs);
  const Nanos res = estimate(bus.batched(16 * kMs)).resolution(kNanosPerMicro);
  EXPECT_GE(res, 15 * kMs);
  EXPECT_LE(res, 20 * kMs);
}

// A poll every half second, each answered within a few ms and read by a 16 ms adapter:
// most reads are a whole exchange, so most intervals between reads are the pauses. Those are
// not the adapter's period (they once gave an estimate of 524 ms, hiding every shorter
// gap); the exchanges that a delivery cut in two show it.
TEST(TimingEstimator, PausesBetweenBurstsAreLeftOut) {
  LineSettings line;
  line.baud = 115200;
  BusBuilder bus(line);
  const auto request = with_crc({0x01, 0x03, 0x00, 0x00, 0x00, 0x1A});
  std::vector<std::uint8_t> response = {0x01, 0x03, 0x34};
  response.resize(3 + 0x34, 0x55);
  const std::uint16_t crc = crc16(response);
  response.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  response.push_back(static_cast<std::uint8_t>(crc >> 8U));
  for (int poll = 0; poll < 24; ++poll) {
    bus.add(request, 500 * kMs).add(response, kMs / 2);
  }
  const auto chunks = bus.batched(16 * kMs);
  ASSERT_LT(chunks.size(), 2 * 24U) << "most exchanges are one read";
  ASSERT_GT(chunks.size(), 24U) << "some exchanges are cut by a delivery";
  const Nanos res = estimate(chunks).resolution(kNanosPerMicro);
  EXPECT_GE(res, 15 * kMs);
  EXPECT_LE(res, 20 * kMs);
}

}  // namespace
}  // namespace rtu
