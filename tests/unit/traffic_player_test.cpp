// The demo's traffic player on a real virtual bus: each burst leaves from its side's
// endpoint, whole and in order, and stop() ends the playing early.
#include "pipeline/traffic_player.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

#include "core/input_error.hpp"
#include "framing/record.hpp"
#include "pipeline/burst_collector.hpp"
#include "serial/virtual_bus.hpp"

namespace rtu {
namespace {

constexpr std::size_t kMasterEndpoint = 0;
constexpr std::size_t kSlaveEndpoint = 1;

bool wait_done(const TrafficPlayer& player) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(15);
  while (!player.done() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return player.done();
}

const LineSettings kLine{19200, Parity::kEven, 1};

VirtualBusOptions three_endpoints() {
  VirtualBusOptions options;
  options.endpoints = 3;
  options.line = kLine;
  return options;
}

TEST(TrafficPlayerTest, PlaysEveryBurstInOrderFromItsSide) {
  VirtualBus bus(three_endpoints());
  bus.start();
  // A request and its answer, twice, then a broadcast; a silence longer than the player
  // keeps (it shortens them) between the two transactions.
  const std::vector<Burst> bursts = {
      {0, false, {0x01, 0x03, 0x00, 0x00, 0x00, 0x01, 0x84, 0x0A}},
      {5 * kNanosPerMilli, true, {0x01, 0x03, 0x02, 0x12, 0x34, 0xB5, 0x33}},
      {900 * kNanosPerMilli, false, {0x02, 0x03, 0x00, 0x10, 0x00, 0x02, 0xC5, 0xFE}},
      {910 * kNanosPerMilli, true, {0x02, 0x03, 0x04, 0x00, 0x01, 0x00, 0x02, 0x2A, 0x32}},
      {950 * kNanosPerMilli, false, {0x00, 0x06, 0x00, 0x01, 0x00, 0x03, 0x98, 0x1A}},
  };
  const unsigned repeat = 2;
  {
    TrafficPlayer player(bursts, repeat, bus.paths()[kMasterEndpoint], bus.paths()[kSlaveEndpoint],
                         kLine.char_time());
    ASSERT_TRUE(wait_done(player));
  }
  bus.stop();

  const auto log = bus.log();
  ASSERT_EQ(log.size(), bursts.size() * repeat);
  for (std::size_t i = 0; i < log.size(); ++i) {
    const Burst& burst = bursts[i % bursts.size()];
    EXPECT_EQ(log[i].bytes, burst.bytes) << "burst " << i;
    EXPECT_EQ(log[i].from, burst.from_slave ? kSlaveEndpoint : kMasterEndpoint) << "burst " << i;
  }
}

TEST(TrafficPlayerTest, StopEndsThePlayingEarly) {
  VirtualBus bus(three_endpoints());
  bus.start();
  // Twenty bursts 200 ms apart: four seconds of traffic.
  std::vector<Burst> bursts;
  for (int i = 0; i < 20; ++i) {
    bursts.push_back({i * 200 * kNanosPerMilli, false, {0x00, 0x06, 0x00, 0x01, 0x00, 0x03}});
  }
  const auto started = std::chrono::steady_clock::now();
  {
    TrafficPlayer player(bursts, 1, bus.paths()[kMasterEndpoint], bus.paths()[kSlaveEndpoint],
                         kLine.char_time());
    std::this_thread::sleep_for(std::chrono::milliseconds(450));
    EXPECT_FALSE(player.done());
    player.stop();
    ASSERT_TRUE(wait_done(player));
  }
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(3));
  bus.stop();
  const std::size_t played = bus.log().size();
  EXPECT_GE(played, 1U);
  EXPECT_LT(played, bursts.size());
}

TEST(TrafficPlayerTest, AnEndpointThatCannotBeOpenedIsAnInputError) {
  VirtualBus bus(three_endpoints());
  EXPECT_THROW(TrafficPlayer({}, 1, bus.paths()[kMasterEndpoint], "/nonexistent/endpoint",
                             kLine.char_time()),
               InputError);
}

TEST(BurstCollectorTest, ResponsesComeFromTheSlavesAtTheirTimeAfterTheFirstRecord) {
  BurstCollector collector;
  const auto feed = [&](Nanos t_start, Role role, std::vector<std::uint8_t> bytes) {
    Record record;
    record.t_start = t_start;
    record.role = role;
    std::copy(bytes.begin(), bytes.end(), record.storage.begin());
    record.size = static_cast<std::uint16_t>(bytes.size());
    collector.on_record(record);
  };
  feed(7 * kNanosPerSecond, Role::kRequest, {0x01, 0x03});
  feed(7 * kNanosPerSecond + 4 * kNanosPerMilli, Role::kResponse, {0x01, 0x83, 0x02});
  feed(8 * kNanosPerSecond, Role::kUnknown, {0xFF});

  ASSERT_EQ(collector.bursts.size(), 3U);
  EXPECT_EQ(collector.bursts[0].at, 0);
  EXPECT_FALSE(collector.bursts[0].from_slave);
  EXPECT_EQ(collector.bursts[0].bytes, (std::vector<std::uint8_t>{0x01, 0x03}));
  EXPECT_EQ(collector.bursts[1].at, 4 * kNanosPerMilli);
  EXPECT_TRUE(collector.bursts[1].from_slave);
  EXPECT_EQ(collector.bursts[1].bytes, (std::vector<std::uint8_t>{0x01, 0x83, 0x02}));
  EXPECT_EQ(collector.bursts[2].at, kNanosPerSecond);
  EXPECT_FALSE(collector.bursts[2].from_slave);
}

}  // namespace
}  // namespace rtu
