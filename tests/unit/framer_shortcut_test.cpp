// Framer::push_if_head_waits() takes a one-byte read without the search push() makes for it,
// where that search is known to leave the head waiting, and push_reads_while_head_waits()
// takes a run of such reads at once. They must change nothing: read by read (or run by
// run), a framer that takes the shortcut wherever it can and one that never does must give
// the same records, hold bytes from the same moment and be ready to decide at the same one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "bus_builder.hpp"
#include "framing/framer.hpp"

namespace rtu {
namespace {

using test::BusBuilder;
using test::ByteRun;
using test::CollectingSink;
using test::with_crc;

constexpr Nanos kMs = kNanosPerMilli;

// Polling with what a sick bus adds: turnaround glitches right after frames and after
// silences, junk, frames back to back, a frame cut by a pause, unanswered requests.
BusBuilder sick_polling(std::uint32_t seed) {
  std::mt19937 random(seed);
  BusBuilder bus;
  const Nanos ch = bus.line().char_time();
  const auto silence = [&] {
    // 33.5 ms: with 30 ms timestamps, a pause that is no silence yet one advance() decides at.
    const Nanos choices[] = {0, ch / 2, 2 * ch, 5 * ch, 3 * kMs, 20 * kMs, 33 * kMs + kMs / 2};
    return choices[random() % 7];
  };
  for (int i = 0; i < 300; ++i) {
    const auto slave = static_cast<std::uint8_t>(1 + random() % 3);
    const auto count = static_cast<std::uint8_t>(1 + random() % 8);
    bus.add(with_crc({slave, 3, 0, 0x10, 0, count}), i % 7 == 0 ? silence() : 4 * kMs);
    if (random() % 5 == 0)
      bus.add({random() % 2 == 0 ? std::uint8_t{0x00} : std::uint8_t{0xFF}}, 0);
    if (random() % 9 == 0) continue;  // unanswered
    std::vector<std::uint8_t> response = {slave, 3, static_cast<std::uint8_t>(2 * count)};
    for (int k = 0; k < 2 * count; ++k) response.push_back(static_cast<std::uint8_t>(random()));
    const std::uint16_t crc = crc16(response);
    response.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
    response.push_back(static_cast<std::uint8_t>(crc >> 8U));
    if (random() % 11 == 0) response[random() % response.size()] ^= 0x04;  // damaged
    if (random() % 13 == 0) {
      // Cut by a pause longer than t3.5 (33.5 ms: see below): two pieces.
      const std::size_t cut = 1 + random() % (response.size() - 1);
      bus.add({response.begin(), response.begin() + static_cast<std::ptrdiff_t>(cut)}, 2 * kMs);
      bus.add({response.begin() + static_cast<std::ptrdiff_t>(cut), response.end()},
              random() % 2 == 0 ? 6 * kMs : 33 * kMs + kMs / 2);
    } else {
      bus.add(response, random() % 6 == 0 ? silence() : 2 * kMs);
    }
    if (random() % 6 == 0) {
      std::vector<std::uint8_t> junk(1 + random() % 5);
      for (auto& b : junk) b = static_cast<std::uint8_t>(random());
      bus.add(junk, silence());
    }
  }
  return bus;
}

// Frames that no length rule bounds, so that the head waits on its CRC search: a vendor's
// function code, random slaves and function codes, some with a CRC-valid first part (a CRC
// zero the search must stop at), mixed with polling, some back to back, some cut by noise.
BusBuilder frames_of_no_length_rule(std::uint32_t seed) {
  std::mt19937 random(seed);
  BusBuilder bus;
  const Nanos ch = bus.line().char_time();
  const auto random_bytes = [&](std::size_t n) {
    std::vector<std::uint8_t> bytes(n);
    for (auto& b : bytes) b = static_cast<std::uint8_t>(random());
    return bytes;
  };
  for (int i = 0; i < 300; ++i) {
    std::vector<std::uint8_t> body = random_bytes(2 + random() % 50);
    switch (random() % 4) {
      case 0: body[1] = 0x41; break;  // a vendor's function code
      case 1: break;                  // any slave and function code
      case 2:
        body[1] = 0x42;
        body = with_crc(body);  // a frame with a CRC-valid first part
        break;
      default: body = {static_cast<std::uint8_t>(1 + random() % 3), 3, 0, 0x10, 0, 2}; break;
    }
    const Nanos gaps[] = {4 * ch, 5 * ch, 10 * ch, 0, ch / 2};
    bus.add(with_crc(body), gaps[random() % 5]);
    if (random() % 10 == 0) bus.add(random_bytes(1 + random() % 3), 4 * ch);
  }
  return bus;
}

// The reads of a per-byte capture of sick polling, with the clock stepping back now and then
// for a few reads (a driver's timestamps do).
std::vector<Chunk> sick_reads(const BusBuilder& bus, std::uint32_t seed) {
  std::vector<Chunk> reads = bus.per_byte();
  std::mt19937 random(seed);
  for (std::size_t i = 50; i + 3 < reads.size(); i += 200 + random() % 200) {
    for (std::size_t k = 0; k < 3; ++k) reads[i + k].t_end -= 3 * bus.line().char_time();
  }
  return reads;
}

struct Moment {
  std::size_t records = 0;
  Nanos oldest_pending = 0;
  Nanos decidable_at = 0;
  bool operator==(const Moment&) const = default;
};

void expect_same_records(const std::vector<Record>& a, const std::vector<Record>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(a[i].kind, b[i].kind);
    EXPECT_TRUE(std::equal(a[i].bytes().begin(), a[i].bytes().end(), b[i].bytes().begin(),
                           b[i].bytes().end()));
    EXPECT_EQ(a[i].t_start, b[i].t_start);
    EXPECT_EQ(a[i].t_end, b[i].t_end);
    EXPECT_EQ(a[i].gap_before, b[i].gap_before);
    EXPECT_EQ(a[i].origin, b[i].origin);
    EXPECT_EQ(a[i].crc_ok, b[i].crc_ok);
    EXPECT_EQ(a[i].shape_fit, b[i].shape_fit);
    EXPECT_EQ(a[i].issues.bits(), b[i].issues.bits());
  }
}

// Two framers fed the same reads: `direct` by the shortcut wherever it takes a read,
// `searched` never by it.
struct DirectAndSearched {
  explicit DirectAndSearched(const FramerConfig& config)
      : direct(config, direct_records), searched(config, searched_records) {}
  // Pushes a one-byte read to both; returns whether the shortcut took it.
  bool push(const Chunk& read) {
    const bool taken = direct.push_if_head_waits(read.bytes[0], read.t_end, read.origin);
    if (!taken) direct.push_without_shortcut(read);
    searched.push_without_shortcut(read);
    return taken;
  }
  void advance(Nanos now) {
    direct.advance(now);
    searched.advance(now);
  }
  [[nodiscard]] Moment direct_moment() const {
    return {direct_records.records.size(), direct.oldest_pending_start(), direct.decidable_at()};
  }
  [[nodiscard]] Moment searched_moment() const {
    return {searched_records.records.size(), searched.oldest_pending_start(),
            searched.decidable_at()};
  }
  // Both finished: they must have given the same records.
  void finish_and_compare() {
    direct.finish();
    searched.finish();
    expect_same_records(direct_records.records, searched_records.records);
  }

  CollectingSink direct_records;
  CollectingSink searched_records;
  Framer direct;
  Framer searched;
};

TEST(FramerShortcut, TakingOneByteReadsDirectlyChangesNothing) {
  for (const std::uint32_t seed : {1U, 2U, 3U}) {
    SCOPED_TRACE(seed);
    const BusBuilder bus = sick_polling(seed);
    const std::vector<Chunk> reads = sick_reads(bus, seed);
    DirectAndSearched framers(FramerConfig{bus.line(), kNanosPerMicro});
    std::size_t taken = 0;
    std::size_t first_bytes_taken = 0;
    std::size_t second_bytes_taken = 0;
    Nanos previous_end = 0;
    for (std::size_t i = 0; i < reads.size(); ++i) {
      SCOPED_TRACE(i);
      const Chunk& read = reads[i];
      const Nanos oldest_before = framers.direct.oldest_pending_start();
      if (framers.push(read)) {
        ++taken;
        if (oldest_before == kUnknownTime) ++first_bytes_taken;
        if (oldest_before == previous_end - bus.line().char_time()) ++second_bytes_taken;
      }
      previous_end = std::max(previous_end + bus.line().char_time(), read.t_end);
      // A live run's quiet moments, now and then between reads.
      if (i % 17 == 0) framers.advance(read.t_end + 2 * kMs);
      ASSERT_EQ(framers.direct_moment(), framers.searched_moment());
    }
    framers.finish_and_compare();
    // The traffic was sick: glitches and junk came out as noise, and frames were found.
    std::size_t noise = 0;
    std::size_t frames = 0;
    for (const Record& r : framers.searched_records.records) {
      noise += r.kind == RecordKind::kNoise ? 1 : 0;
      frames += r.kind == RecordKind::kFrame && r.crc_ok ? 1 : 0;
    }
    EXPECT_GT(noise, 40U);
    EXPECT_GT(frames, 400U);
    // And the shortcut was taken: for most bytes, frames' first and second bytes among them.
    EXPECT_GT(taken, reads.size() / 2);
    EXPECT_GT(first_bytes_taken, frames / 2);
    EXPECT_GT(second_bytes_taken, frames / 2);
  }
}

TEST(FramerShortcut, HeadsThatWaitOnTheirCrcSearchTakeBytesDirectlyAndChangeNothing) {
  for (const std::uint32_t seed : {1U, 2U, 3U}) {
    SCOPED_TRACE(seed);
    const BusBuilder bus = frames_of_no_length_rule(seed);
    const std::vector<Chunk> reads = bus.per_byte();
    DirectAndSearched framers(FramerConfig{bus.line(), kNanosPerMicro});
    std::size_t taken = 0;
    for (std::size_t i = 0; i < reads.size(); ++i) {
      SCOPED_TRACE(i);
      if (framers.push(reads[i])) ++taken;
      ASSERT_EQ(framers.direct_moment(), framers.searched_moment());
    }
    framers.finish_and_compare();
    // Frames of no length rule were found whole, the ones with a CRC-valid first part too.
    std::size_t vendor_frames = 0;
    for (const Record& r : framers.searched_records.records) {
      if (r.kind == RecordKind::kFrame && r.crc_ok && r.size > 2 && r.bytes()[1] == 0x42) {
        ++vendor_frames;
      }
    }
    EXPECT_GT(vendor_frames, 40U);
    // Half the bytes were taken directly, where the CRC searches waited as polling's fixed
    // lengths do (a tenth, where only the polling heads were).
    EXPECT_GT(taken, reads.size() / 3);
  }
}

TEST(FramerShortcut, TakingRunsOfReadsAtOnceChangesNothing) {
  const BusBuilder bus = sick_polling(4);
  const std::vector<Chunk> reads = sick_reads(bus, 4);
  const ByteRun run_of_reads(reads);
  // Exact timestamps, and coarse ones (longer than the framer's delivery patience: a read
  // after a pause too short to show as a silence may still come when advance() decides).
  for (const Nanos resolution : {kNanosPerMicro, 30 * kMs})
    for (const std::size_t run : {1U, 2U, 5U, 64U, 100000U}) {
      SCOPED_TRACE(run);
      SCOPED_TRACE(resolution);
      const FramerConfig config{bus.line(), resolution};
      CollectingSink run_records;
      CollectingSink searched_records;
      Framer by_runs(config, run_records);
      Framer searched(config, searched_records);
      std::size_t searched_up_to = 0;  // reads pushed to `searched`
      std::size_t taken = 0;
      std::size_t longest = 0;
      for (std::size_t first = 0; first < reads.size(); first += run) {
        const std::size_t size = std::min(run, reads.size() - first);
        const ByteReads piece = run_of_reads.slice(first, size, reads[first].origin);
        for (std::size_t i = 0; i < size;) {
          Nanos latest = kUnknownTime;
          const std::size_t n = by_runs.push_reads_while_head_waits(piece, i, latest);
          if (n > 0) {
            EXPECT_EQ(latest, *std::max_element(piece.t_ends + i, piece.t_ends + i + n));
            taken += n;
            longest = std::max(longest, n);
            i += n;
          }
          if (i < size) {
            by_runs.push_without_shortcut(piece.read(i));
            ++i;
          }
          for (; searched_up_to < first + i; ++searched_up_to) {
            searched.push_without_shortcut(reads[searched_up_to]);
          }
          ASSERT_EQ(run_records.records.size(), searched_records.records.size())
              << "after read " << first + i;
          ASSERT_EQ(by_runs.oldest_pending_start(), searched.oldest_pending_start())
              << "after read " << first + i;
          ASSERT_EQ(by_runs.decidable_at(), searched.decidable_at()) << "after read " << first + i;
        }
      }
      by_runs.finish();
      searched.finish();
      expect_same_records(run_records.records, searched_records.records);
      EXPECT_GT(taken, reads.size() / 3);  // coarse timestamps: fewer (48%)
      // Runs were taken whole: a request's four bytes after its first search, a long
      // response's dozen.
      if (run >= 64) {
        EXPECT_GE(longest, 10U);
      }
    }
}

}  // namespace
}  // namespace rtu
