// Live ≡ replay: a live run calls DecodePipeline::idle() whenever its timer finds the line
// quiet, at times no recording keeps; the replay of its recording only sees the reads.
// Both must give identical records, for any chunking and any idle times. Traffic here is
// deliberately sick: damaged and truncated frames, slaves that never answer, glitch bytes,
// noise, and answers faster than t1.5.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "bus_builder.hpp"
#include "pipeline/decode_pipeline.hpp"

namespace rtu {
namespace {

using test::BusBuilder;
using test::CollectingSink;
using test::with_crc;

constexpr Nanos kUs = kNanosPerMicro;
constexpr Nanos kMs = kNanosPerMilli;

// A record as the outputs show it.
std::string describe(const Record& r) {
  std::string s = r.kind == RecordKind::kFrame ? "frame " : "noise ";
  for (const auto b : r.bytes()) s += fmt::format("{:02x}", b);
  s += fmt::format(" t={} end={} gap={} crc={} role={} txn={} lat={} issues={:x}", r.t_start,
                   r.t_end, r.gap_before, r.crc_ok, static_cast<int>(r.role), r.txn, r.latency,
                   r.issues.bits());
  return s;
}

std::vector<std::uint8_t> random_request(std::mt19937& rng, std::uint8_t slave) {
  const auto addr = static_cast<std::uint8_t>(rng() % 200);
  switch (rng() % 3) {
    case 0:
      return with_crc({slave, 0x03, 0x00, addr, 0x00, static_cast<std::uint8_t>(1 + rng() % 20)});
    case 1: return with_crc({slave, 0x06, 0x00, addr, 0x12, 0x34});
    default: return with_crc({slave, 0x04, 0x00, addr, 0x00, 0x02});
  }
}

std::vector<std::uint8_t> response_to(const std::vector<std::uint8_t>& req, std::mt19937& rng) {
  if (rng() % 15 == 0) return with_crc({req[0], static_cast<std::uint8_t>(req[1] | 0x80U), 0x02});
  if (req[1] == 0x06) return req;
  const std::size_t words = req[1] == 0x04 ? 2 : req[5];
  std::vector<std::uint8_t> body = {req[0], req[1], static_cast<std::uint8_t>(2 * words)};
  for (std::size_t i = 0; i < 2 * words; ++i) body.push_back(static_cast<std::uint8_t>(rng()));
  const std::uint16_t crc = crc16(body);
  body.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  body.push_back(static_cast<std::uint8_t>(crc >> 8U));
  return body;
}

// Sick traffic: roughly one transaction in four has something wrong with it.
BusBuilder sick_bus(std::uint32_t baud, std::uint32_t seed) {
  LineSettings line;
  line.baud = baud;
  BusBuilder bus(line);
  std::mt19937 rng(seed);
  const Nanos ct = line.char_time();
  for (int i = 0; i < 120; ++i) {
    const auto slave = static_cast<std::uint8_t>(1 + rng() % 3);
    auto req = random_request(rng, slave);
    auto resp = response_to(req, rng);
    const unsigned fault = rng() % 16;
    if (fault == 0) req[rng() % req.size()] ^= static_cast<std::uint8_t>(1U << (rng() % 8));
    if (fault == 1) resp[rng() % resp.size()] ^= static_cast<std::uint8_t>(1U << (rng() % 8));
    if (fault == 2) resp.resize(1 + rng() % (resp.size() - 1));
    // Polls 3-43 ms apart, now and then after a pause longer than the response timeout.
    const auto pause = static_cast<Nanos>(rng() % 8 == 0 ? 60 + rng() % 40 : 3 + rng() % 40);
    bus.add(req, pause * kMs);
    if (fault == 3) continue;  // the slave never answers
    // Answers from 0.1 ms (faster than t1.5 at 115200) to several character times, and
    // now and then one after the response timeout (late).
    const Nanos answer = fault == 6 ? static_cast<Nanos>(45 + rng() % 15) * kMs
                                    : 100 * kUs + static_cast<Nanos>(rng() % 6) * ct;
    bus.add(resp, answer);
    if (fault == 4) bus.add({0xFE}, 100 * kUs);  // turnaround glitch
    if (fault == 5) bus.add({0x00, 0xFF, 0x3C}, static_cast<Nanos>(rng() % 3) * kMs);
  }
  return bus;
}

PipelineOptions options_for(const BusBuilder& bus, Nanos prior) {
  PipelineOptions options;
  options.line = bus.line();
  options.timing_resolution = prior;
  options.response_timeout = 50 * kMs;
  return options;
}

std::vector<std::string> replay(const std::vector<Chunk>& chunks, const PipelineOptions& options,
                                Nanos end) {
  CollectingSink sink;
  DecodePipeline pipeline(options, sink);
  for (const auto& c : chunks) pipeline.push(c);
  pipeline.idle(end);  // the recording's CAPTURE_COMPLETE
  pipeline.finish();
  std::vector<std::string> out;
  for (const auto& r : sink.records) out.push_back(describe(r));
  return out;
}

// Live: idle() at every `step` (with jitter) while no read has completed.
std::vector<std::string> live(const std::vector<Chunk>& chunks, const PipelineOptions& options,
                              Nanos end, Nanos step, std::uint32_t seed) {
  CollectingSink sink;
  DecodePipeline pipeline(options, sink);
  std::mt19937 rng(seed);
  Nanos now = chunks.empty() ? 0 : chunks.front().t_end;
  for (const auto& c : chunks) {
    while (now + step < c.t_end) {
      now += step / 2 + static_cast<Nanos>(rng() % static_cast<std::uint32_t>(step));
      if (now < c.t_end) pipeline.idle(now);
    }
    pipeline.push(c);
    now = c.t_end;
  }
  for (; now < end; now += step) pipeline.idle(now);
  pipeline.idle(end);
  pipeline.finish();
  std::vector<std::string> out;
  for (const auto& r : sink.records) out.push_back(describe(r));
  return out;
}

struct Adapter {
  const char* name;
  Nanos latency;  // 0 = per-byte reads
  std::size_t packet;
  Nanos prior;  // what the port claimed when opened
};

class LiveEqualsReplay : public ::testing::TestWithParam<std::tuple<std::uint32_t, Adapter>> {};

TEST_P(LiveEqualsReplay, SameRecordsForAnyIdleTimes) {
  const auto [baud, adapter] = GetParam();
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    const BusBuilder bus = sick_bus(baud, seed);
    const auto chunks =
        adapter.latency == 0 ? bus.per_byte() : bus.usb(adapter.latency, adapter.packet);
    const PipelineOptions options = options_for(bus, adapter.prior);
    const Nanos end = chunks.back().t_end + 200 * kMs;
    const auto replayed = replay(chunks, options, end);
    for (const Nanos step : {300 * kUs, 1 * kMs, 5 * kMs}) {
      const auto lived = live(chunks, options, end, step, seed);
      ASSERT_EQ(lived.size(), replayed.size()) << adapter.name << " seed " << seed;
      for (std::size_t i = 0; i < lived.size(); ++i) {
        ASSERT_EQ(lived[i], replayed[i]) << adapter.name << " seed " << seed << " record " << i;
      }
    }
    std::size_t bytes = 0;
    for (const auto& c : chunks) bytes += c.bytes.size();
    EXPECT_EQ(bytes, bus.size());
  }
}

INSTANTIATE_TEST_SUITE_P(
    Adapters, LiveEqualsReplay,
    ::testing::Combine(::testing::Values(9600U, 115200U),
                       ::testing::Values(Adapter{"per-byte", 0, 0, kMs},
                                         Adapter{"usb-1ms-p4", kMs, 4, kMs},
                                         Adapter{"usb-16ms-p62", 16 * kMs, 62, kMs},
                                         Adapter{"usb-8ms-p16", 8 * kMs, 16, kMs},
                                         Adapter{"usb-16ms-p8-known", 16 * kMs, 8, 16 * kMs})));

// Every frame of the sick bus that came through whole is decoded whole, on any adapter,
// even when the port claimed 1 ms and the adapter held bytes for 16 ms.
TEST(LiveEqualsReplay, UsbAdapterThatHidesItsLatencyLosesNoCleanFrame) {
  LineSettings line;
  line.baud = 115200;
  BusBuilder bus(line);
  std::vector<std::vector<std::uint8_t>> sent;
  std::mt19937 rng(7);
  for (int i = 0; i < 60; ++i) {
    auto req = random_request(rng, 0x11);
    auto resp = response_to(req, rng);
    bus.add(req, static_cast<Nanos>(20 + rng() % 30) * kMs);
    bus.add(resp, static_cast<Nanos>(100 + rng() % 600) * kUs);
    sent.push_back(req);
    sent.push_back(resp);
  }
  for (const std::size_t packet : {4U, 8U, 62U}) {
    const auto chunks = bus.usb(16 * kMs, packet);
    const PipelineOptions options = options_for(bus, kMs);
    const auto lived = live(chunks, options, chunks.back().t_end + 100 * kMs, 1 * kMs, 1);
    if (lived.size() != sent.size()) {
      for (const auto& l : lived) std::cerr << l << "\n";
    }
    ASSERT_EQ(lived.size(), sent.size()) << "packet " << packet;
    for (std::size_t i = 0; i < sent.size(); ++i) {
      std::string hex;
      for (const auto b : sent[i]) hex += fmt::format("{:02x}", b);
      EXPECT_EQ(lived[i].substr(0, 6 + hex.size()), "frame " + hex) << "packet " << packet;
      EXPECT_NE(lived[i].find("crc=true"), std::string::npos);
      // No false t1.5 flag where a USB packet boundary cut the frame.
      const auto t15 = std::uint64_t{1} << static_cast<unsigned>(IssueId::kT15);
      const auto bits = std::stoull(lived[i].substr(lived[i].rfind('=') + 1), nullptr, 16);
      EXPECT_EQ(bits & t15, 0U) << lived[i];
    }
  }
}

}  // namespace
}  // namespace rtu
