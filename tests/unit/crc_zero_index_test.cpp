// The CRC search from a start (a CrcScan) as CrcZeroIndex answers it: the same zero lengths
// as the byte-at-a-time definition, from any start, however the search is resumed, and
// however the framer's window moves along the stream (also past bytes never searched, and
// round the index's ring of values many times).
#include "framing/crc_zero_index.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "core/crc16.hpp"

namespace rtu {
namespace {

// The definition: the lengths (>= kMinAdu) at which the CRC from `start` is zero.
std::vector<std::size_t> zeros_by_definition(const std::vector<std::uint8_t>& bytes,
                                             std::size_t start, std::size_t length) {
  std::vector<std::size_t> zeros;
  std::uint16_t crc = kCrcInit;
  for (std::size_t i = 0; i < length; ++i) {
    crc = crc16_update(crc, bytes[start + i]);
    if (crc == 0 && i + 1 >= kMinAdu) zeros.push_back(i + 1);
  }
  return zeros;
}

std::vector<std::size_t> zeros_of(const CrcScan& scan) {
  std::vector<std::size_t> out;
  scan.any_zero_length([&out](std::size_t length) {
    out.push_back(length);
    return false;
  });
  return out;
}

// Bytes made of CRC-valid frames back to back, so that zeros are many, not one in 65,536.
std::vector<std::uint8_t> frames_back_to_back(std::mt19937& rng, std::size_t size) {
  std::vector<std::uint8_t> bytes;
  while (bytes.size() < size) {
    // Now and then a few stray bytes, so that frames do not start only where others end.
    for (std::size_t k = rng() % 8 == 0 ? rng() % 5 : 0; k > 0; --k) {
      bytes.push_back(static_cast<std::uint8_t>(rng()));
    }
    const std::size_t body = 2 + rng() % 12;
    std::vector<std::uint8_t> frame;
    for (std::size_t i = 0; i < body; ++i) frame.push_back(static_cast<std::uint8_t>(rng()));
    const std::uint16_t crc = crc16(frame);
    frame.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
    frame.push_back(static_cast<std::uint8_t>(crc >> 8U));
    bytes.insert(bytes.end(), frame.begin(), frame.end());
  }
  return bytes;
}

// A window over the stream that moves on as a framer's does (by a frame, by a long stretch
// that was never searched), with searches from random starts in it, each resumed a few
// times over more bytes: every search gives exactly the definition's zero lengths.
TEST(CrcZeroIndex, EverySearchFindsTheByteAtATimeZerosAsTheWindowMovesOn) {
  std::mt19937 rng(20261202);
  const std::vector<std::uint8_t> bytes = frames_back_to_back(rng, 200'000);
  constexpr std::size_t kWindow = 2048;
  CrcZeroIndex index;
  std::size_t window_start = 0;
  std::size_t zeros_seen = 0;
  std::size_t crossings = 0;  // searches that reached into the next block
  while (window_start + kWindow + kMaxAdu < bytes.size()) {
    for (int search = 0; search < 30; ++search) {
      const std::size_t start = window_start + rng() % (kWindow - kMaxAdu);
      CrcScan scan;
      scan.start = start;
      std::size_t length = 0;
      while (length < kMaxAdu) {
        length = std::min(kMaxAdu, length + 1 + rng() % 90);
        index.note_zeros(scan, length, bytes.data() + window_start, window_start);
        ASSERT_EQ(scan.scanned, length);
        const std::vector<std::size_t> expected = zeros_by_definition(bytes, start, length);
        ASSERT_EQ(zeros_of(scan), expected) << "start " << start << " length " << length;
        ASSERT_EQ(scan.found_zero, !expected.empty());
      }
      zeros_seen += zeros_of(scan).size();
      if (start % CrcZeroIndex::kBlock + kMaxAdu >= CrcZeroIndex::kBlock) ++crossings;
    }
    // On by a frame or so, and now and then past a stretch nobody searched.
    window_start += rng() % 10 == 0 ? kWindow + rng() % 5000 : 1 + rng() % 300;
  }
  EXPECT_GT(zeros_seen, 1000U) << "the bytes must give the zero tests work";
  EXPECT_GT(crossings, 100U) << "searches must reach into the next block";
}

// One byte at a time, as per-byte reads extend a search: the same zeros again.
TEST(CrcZeroIndex, SearchesResumedOneByteAtATimeFindTheSameZeros) {
  std::mt19937 rng(7);
  const std::vector<std::uint8_t> bytes = frames_back_to_back(rng, 20'000);
  CrcZeroIndex index;
  for (std::size_t start = 0; start + kMaxAdu < bytes.size(); start += 1 + rng() % 97) {
    CrcScan scan;
    scan.start = start;
    for (std::size_t length = 1; length <= kMaxAdu; ++length) {
      index.note_zeros(scan, length, bytes.data() + start, start);
    }
    ASSERT_EQ(zeros_of(scan), zeros_by_definition(bytes, start, kMaxAdu)) << "start " << start;
  }
}

TEST(CrcZeroIndex, ZerosShorterThanTheSmallestFrameAreNotLengths) {
  // Two bytes whose CRC is zero: not a frame (fewer than four bytes), so not a length.
  std::vector<std::uint8_t> bytes;
  for (unsigned v = 0; v <= 0xFFFFU && bytes.empty(); ++v) {
    const std::vector<std::uint8_t> two = {static_cast<std::uint8_t>(v >> 8U),
                                           static_cast<std::uint8_t>(v & 0xFFU)};
    if (crc16(two) == 0) bytes = two;
  }
  ASSERT_EQ(bytes.size(), 2U);
  for (int i = 0; i < 40; ++i) bytes.push_back(static_cast<std::uint8_t>(i * 37));
  CrcZeroIndex index;
  CrcScan scan;
  scan.start = 0;
  index.note_zeros(scan, bytes.size(), bytes.data(), 0);
  const std::vector<std::size_t> zeros = zeros_of(scan);
  EXPECT_EQ(std::count(zeros.begin(), zeros.end(), 2U), 0);
  EXPECT_EQ(zeros, zeros_by_definition(bytes, 0, bytes.size()));
}

}  // namespace
}  // namespace rtu
