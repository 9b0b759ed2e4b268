// Remembering which start positions wait quietly (framing/quiet_starts.hpp) only saves
// searches: the framer must give the same records with and without it, on traffic where
// nearly every byte may start a frame and on ordinary polling, read per byte and batched.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "bus_builder.hpp"
#include "core/crc16.hpp"
#include "framing/framer.hpp"

namespace rtu {
namespace {

using test::BusBuilder;
using test::CollectingSink;

constexpr Nanos kMs = kNanosPerMilli;

// CRC-valid frames of random slaves and function codes with 0-60 data bytes, now and then
// a damaged one or a few bytes of junk, apart by silences from none to several t3.5.
BusBuilder random_bus(std::uint32_t seed, int frames) {
  std::mt19937 random(seed);
  const auto byte = [&] { return static_cast<std::uint8_t>(random() & 0xFFU); };
  BusBuilder bus;
  const Nanos silences[] = {0, bus.line().char_time() / 2, 2 * bus.line().char_time(),
                            5 * bus.line().char_time(), 20 * kMs};
  for (int i = 0; i < frames; ++i) {
    std::vector<std::uint8_t> body = {byte(), byte()};
    if (random() % 4 == 0) body = {1, 3, 0, 0, 0, 2};  // ordinary polling in between
    for (std::size_t n = random() % 61; n > 0; --n) body.push_back(byte());
    std::vector<std::uint8_t> frame = body;
    const std::uint16_t crc = crc16(body);
    frame.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
    frame.push_back(static_cast<std::uint8_t>(crc >> 8U));
    if (random() % 10 == 0) frame[random() % frame.size()] ^= 0x10;  // damaged
    if (random() % 8 == 0) {
      std::vector<std::uint8_t> junk(1 + random() % 4);
      for (auto& b : junk) b = byte();
      bus.add(junk, silences[random() % 5]);
    }
    bus.add(frame, silences[random() % 5]);
  }
  return bus;
}

std::vector<Record> frame_all(const std::vector<Chunk>& chunks, FramerConfig config,
                              bool remember) {
  CollectingSink sink;
  config.remember_quiet_starts = remember;
  Framer framer(config, sink);
  for (const auto& c : chunks) {
    framer.push(c);
    framer.advance(c.t_end + 3 * kMs);  // a moment of quiet, as the live idle timer gives
  }
  framer.finish();
  return sink.records;
}

void expect_same_records(const std::vector<Record>& a, const std::vector<Record>& b,
                         const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Record& x = a[i];
    const Record& y = b[i];
    ASSERT_EQ(x.kind, y.kind) << what << " record " << i;
    ASSERT_TRUE(std::equal(x.bytes().begin(), x.bytes().end(), y.bytes().begin(), y.bytes().end()))
        << what << " record " << i;
    ASSERT_EQ(x.t_start, y.t_start) << what << " record " << i;
    ASSERT_EQ(x.t_end, y.t_end) << what << " record " << i;
    ASSERT_EQ(x.gap_before, y.gap_before) << what << " record " << i;
    ASSERT_EQ(x.crc_ok, y.crc_ok) << what << " record " << i;
    ASSERT_EQ(x.shape_fit, y.shape_fit) << what << " record " << i;
    ASSERT_EQ(x.issues.bits(), y.issues.bits()) << what << " record " << i;
  }
}

TEST(QuietStarts, RememberingChangesNoRecord) {
  for (const std::uint32_t seed : {1U, 2U, 3U}) {
    const BusBuilder bus = random_bus(seed, 400);
    struct Reading {
      std::string name;
      std::vector<Chunk> chunks;
      FramerConfig config;
    };
    const std::vector<Reading> readings = {
        {"per byte", bus.per_byte(), FramerConfig{bus.line(), kNanosPerMicro}},
        {"1 ms reads", bus.batched(1 * kMs), FramerConfig{bus.line(), 1 * kMs}},
        {"16 ms reads", bus.batched(16 * kMs), FramerConfig{bus.line(), 16 * kMs}},
        {"16 ms reads, resolution unknown", bus.batched(16 * kMs), FramerConfig{bus.line(), 0}},
        // Reads of a few bytes: watched starts run on over two or three bytes at once; over
        // a USB packet's where a stretch forms nothing, and a longer read ends every watch.
        {"reads of up to 3 bytes", bus.usb(2 * kMs, 3), FramerConfig{bus.line(), 2 * kMs}},
        {"reads of up to 5 bytes", bus.usb(2 * kMs, 5), FramerConfig{bus.line(), 2 * kMs}},
        {"reads of up to 62 bytes", bus.usb(16 * kMs, 62), FramerConfig{bus.line(), 16 * kMs}},
        {"reads of up to 100 bytes", bus.usb(64 * kMs, 100), FramerConfig{bus.line(), 64 * kMs}}};
    std::size_t frames = 0;
    for (const auto& reading : readings) {
      const auto with = frame_all(reading.chunks, reading.config, true);
      const auto without = frame_all(reading.chunks, reading.config, false);
      const std::string what = reading.name + ", seed " + std::to_string(seed);
      expect_same_records(with, without, what);
      for (const auto& r : with) frames += r.kind == RecordKind::kFrame && r.crc_ok ? 1 : 0;
    }
    // The searches were exercised: frames were found, not only noise. (Random slaves and
    // function codes sent back to back or behind junk are hard: per byte about 60% of the
    // intact frames are found, through 16 ms reads about 15%.)
    EXPECT_GT(frames, 400U) << "seed " << seed;
  }
}

// Long stretches of noise, where some 250 starts wait on their CRC searches at every byte
// and nearly all are watched, with frames and silences between them.
TEST(QuietStarts, WatchingNoiseChangesNoRecord) {
  std::mt19937 random(7);
  const auto byte = [&] { return static_cast<std::uint8_t>(random() & 0xFFU); };
  BusBuilder bus;
  for (int stretch = 0; stretch < 12; ++stretch) {
    std::vector<std::uint8_t> noise(300 + random() % 1500);
    for (auto& b : noise) b = byte();
    bus.add(noise, stretch % 3 == 0 ? 20 * kMs : 0);
    bus.add(test::with_crc({1, 3, 0, 0, 0, 2}), stretch % 2 == 0 ? 5 * kMs : 0);
  }
  // Reads of up to 28 bytes (16 ms of a USB adapter's latency) are watched across once the
  // window holds a stretch of noise (Framer::kWatchedStretch).
  const std::vector<std::tuple<std::string, std::vector<Chunk>, Nanos>> readings = {
      {"per byte", bus.per_byte(), kNanosPerMicro},
      {"reads of up to 2 bytes", bus.usb(1 * kMs, 2), kNanosPerMicro},
      {"reads of up to 28 bytes", bus.usb(16 * kMs, 62), 16 * kMs}};
  for (const auto& [name, chunks, resolution] : readings) {
    const FramerConfig config{bus.line(), resolution};
    const auto with = frame_all(chunks, config, true);
    const auto without = frame_all(chunks, config, false);
    expect_same_records(with, without, name);
    std::size_t noise = 0;
    for (const auto& r : with) noise += r.kind == RecordKind::kNoise ? r.size : 0;
    EXPECT_GT(noise, 3000U) << name;  // it was noise, kept as noise
  }
}

// The watch itself: what ends it, and only that.
TEST(QuietStarts, AWatchEndsAtAZeroOfItsCrcAtItsUntilOrWhenAsked) {
  QuietStarts quiet;
  CrcZeroIndex zeros;
  // The stream from position 100 on: a frame.
  const std::vector<std::uint8_t> frame = test::with_crc({7, 0x41, 1, 2, 3});
  const auto grow_to = [&](std::uint64_t end) {
    zeros.compute_through(end, frame.data(), 100);
    quiet.run_on(zeros, end);
  };
  // Start 100 waits on its CRC search, which has run over the frame's first three bytes.
  const QuietStart searching{100, 1, 100 + kMaxAdu, true, true, false};
  quiet.remember(searching);
  quiet.unwatch_all(103);
  zeros.compute_through(103, frame.data(), 100);
  EXPECT_TRUE(quiet.watch(searching, zeros));
  EXPECT_EQ(quiet.watched_answer(100), QuietStarts::kQuietPending);
  // Start 101 waits for a predicted length only, up to window end 106.
  const QuietStart predicted{101, 1, 106, false, false, true};
  quiet.remember(predicted);
  EXPECT_TRUE(quiet.watch(predicted, zeros));
  EXPECT_EQ(quiet.watched_answer(101), QuietStarts::kQuiet);

  grow_to(104);  // no zero yet, and 104 is short of 106
  EXPECT_EQ(quiet.watched_answer(100), QuietStarts::kQuietPending);
  EXPECT_EQ(quiet.watched_answer(101), QuietStarts::kQuiet);
  grow_to(106);  // one of the CRC's bytes; the window reaches 106
  EXPECT_EQ(quiet.watched_answer(100), QuietStarts::kQuietPending);
  EXPECT_EQ(quiet.watched_answer(101), QuietStarts::kNotWatched);
  grow_to(107);  // the CRC's last byte: the CRC from 100 is zero
  EXPECT_EQ(quiet.watched_answer(100), QuietStarts::kNotWatched);
  EXPECT_FALSE(quiet.any_watched());

  // A start that left the window, and remembering anew, end a watch too.
  const QuietStart a{200, 2, 300, false, true, false};
  const QuietStart b{201, 2, 300, false, true, false};
  quiet.remember(a);
  quiet.remember(b);
  quiet.watch(a, zeros);
  quiet.watch(b, zeros);
  quiet.unwatch_range(200, 1);
  EXPECT_EQ(quiet.watched_answer(200), QuietStarts::kNotWatched);
  EXPECT_EQ(quiet.watched_answer(201), QuietStarts::kQuietPending);
  quiet.remember(b);
  EXPECT_EQ(quiet.watched_answer(201), QuietStarts::kNotWatched);
  quiet.watch(b, zeros);
  quiet.unwatch_all(108);
  EXPECT_FALSE(quiet.any_watched());
  EXPECT_EQ(quiet.watched_through(), 108U);
}

// Watches taken on byte by byte end exactly where their CRC comes out zero, also where
// the search crosses from one of CrcZeroIndex's blocks into the next (each watch's target
// moves on there), and stay on everywhere else: checked against the CRC run byte by byte.
TEST(QuietStarts, WatchedCrcSearchesEndAtTheirZerosAcrossBlocks) {
  std::mt19937 random(5);
  std::size_t zeros_met = 0;
  std::size_t crossings = 0;
  for (int round = 0; round < 40; ++round) {
    // Random bytes, with CRC-valid frames laid in from random starts.
    std::vector<std::uint8_t> stream(1200);
    for (auto& b : stream) b = static_cast<std::uint8_t>(random() & 0xFFU);
    for (int f = 0; f < 6; ++f) {
      const std::size_t at = random() % 1000;
      const std::size_t length = 4 + random() % 150;
      const std::uint16_t crc = crc16({stream.data() + at, length - 2});
      stream[at + length - 2] = static_cast<std::uint8_t>(crc & 0xFFU);
      stream[at + length - 1] = static_cast<std::uint8_t>(crc >> 8U);
    }
    QuietStarts quiet;
    CrcZeroIndex zeros;
    const std::uint64_t first = random() % 300;  // the window's start: the chain's origin
    quiet.unwatch_all(first);
    // Each start is watched once the window holds it and one more byte, until kMaxAdu on.
    std::vector<std::uint16_t> crc(stream.size(), kCrcInit);
    std::vector<bool> live(stream.size(), false);
    for (std::uint64_t end = first + 1; end <= stream.size(); ++end) {
      zeros.compute_through(end, stream.data() + first, first);
      quiet.run_on(zeros, end);
      for (std::uint64_t start = first; start + 1 < end; ++start) {
        if (!live[start]) continue;
        crc[start] = crc16_update(crc[start], stream[end - 1]);
        const bool ends = crc[start] == 0 || end >= start + kMaxAdu;
        zeros_met += crc[start] == 0 ? 1U : 0U;
        const auto block_of = [first](std::uint64_t p) {
          return (p - first) / CrcZeroIndex::kBlock;
        };
        if (crc[start] == 0 && block_of(start) != block_of(end)) ++crossings;
        ASSERT_EQ(quiet.watched_answer(start) != QuietStarts::kNotWatched, !ends)
            << "round " << round << " start " << start << " window end " << end;
        live[start] = !ends;
      }
      const std::uint64_t start = end - 1;
      const QuietStart entry{start, 1, start + kMaxAdu, true, true, false};
      quiet.remember(entry);
      zeros.compute_through(end, stream.data() + first, first);
      ASSERT_TRUE(quiet.watch(entry, zeros));
      crc[start] = crc16_update(kCrcInit, stream[start]);
      live[start] = true;
    }
  }
  EXPECT_GT(zeros_met, 200U);  // the laid-in frames' CRCs, met by the watches
  EXPECT_GT(crossings, 20U);
}

// A watch that ends at the longest frame with no CRC zero, having waited on its CRC search
// alone, gives its start up as settled; one that also waits for bytes does not, nor one of
// another epoch than the one asked about.
TEST(QuietStarts, AWatchThatReachesTheLongestFrameWithNoZeroIsExhausted) {
  std::vector<std::uint8_t> stream(600);
  std::mt19937 random(9);
  for (auto& b : stream) b = static_cast<std::uint8_t>(random() & 0xFFU);
  for (const std::uint64_t epoch : {std::uint64_t{1}, std::uint64_t{2}}) {
    QuietStarts quiet;
    CrcZeroIndex zeros;
    quiet.unwatch_all(12);
    zeros.compute_through(12, stream.data(), 0);
    const QuietStart searching{10, 1, 10 + kMaxAdu, true, false, true};
    const QuietStart also_pending{11, 1, 11 + kMaxAdu, true, true, true};
    quiet.remember(searching);
    quiet.remember(also_pending);
    ASSERT_TRUE(quiet.watch(searching, zeros));
    ASSERT_TRUE(quiet.watch(also_pending, zeros));
    std::vector<std::uint64_t> settled;
    for (std::uint64_t end = 13; end <= 11 + kMaxAdu; ++end) {
      zeros.compute_through(end, stream.data(), 0);
      quiet.run_on(zeros, end);
      quiet.take_exhausted(epoch, [&](std::uint64_t start) { settled.push_back(start); });
    }
    // These bytes hold no CRC zero from either start (else the watch would have ended
    // there, and the start would not be given up).
    EXPECT_FALSE(quiet.any_watched());
    if (epoch == 1) {
      EXPECT_EQ(settled, std::vector<std::uint64_t>{10});
    } else {
      EXPECT_TRUE(settled.empty());
    }
  }
}

// skip_watched() answers what asking each start's watched_answer() in turn would, a word of
// starts at a time, round the ring of slots too.
TEST(QuietStarts, SkippingWatchedStartsAgreesWithAskingEachOne) {
  std::mt19937 random(11);
  const CrcZeroIndex no_values;  // no watch here waits on its CRC search
  for (const std::uint64_t base : {std::uint64_t{0}, std::uint64_t{1500}, std::uint64_t{4090}}) {
    QuietStarts quiet;
    quiet.unwatch_all(base + 1024);
    for (std::uint64_t start = base; start < base + 1024; ++start) {
      if (random() % 16 == 0) continue;  // a start that is not watched
      const QuietStart entry{start, 1, base + 2000, false, random() % 4 == 0, false};
      quiet.remember(entry);
      quiet.watch(entry, no_values);
    }
    for (int ask = 0; ask < 2000; ++ask) {
      const std::uint64_t from = base + random() % 1024;
      const std::uint64_t to = from + random() % (base + 1025 - from);
      std::uint64_t expected_stop = to;
      std::uint64_t expected_pending = QuietStarts::kNone;
      for (std::uint64_t start = from; start < to; ++start) {
        const auto answer = quiet.watched_answer(start);
        if (answer == QuietStarts::kNotWatched) {
          expected_stop = start;
          break;
        }
        if (answer == QuietStarts::kQuietPending && expected_pending == QuietStarts::kNone) {
          expected_pending = start;
        }
      }
      std::uint64_t pending = QuietStarts::kNone;
      ASSERT_EQ(quiet.skip_watched(from, to, pending), expected_stop) << from << ".." << to;
      ASSERT_EQ(pending, expected_pending) << from << ".." << to;
      // A pending start found earlier is kept.
      std::uint64_t earlier = from;
      ASSERT_EQ(quiet.skip_watched(from, to, earlier), expected_stop);
      ASSERT_EQ(earlier, from);
    }
  }
}

}  // namespace
}  // namespace rtu
