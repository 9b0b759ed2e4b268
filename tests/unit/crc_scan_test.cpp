// The CRC search's record of one start (CrcScan), and four of them run side by side: the
// same CRC and the same zero lengths as the byte-at-a-time definition, whatever each scan
// had covered before and however far each runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <vector>

#include "core/crc16.hpp"
#include "framing/crc_scan_cache.hpp"

namespace rtu {
namespace {

// The definition: the CRC from `start` after each length, and the lengths (>= kMinAdu) at
// which it is zero.
struct Expected {
  std::uint16_t crc = kCrcInit;
  std::vector<std::size_t> zeros;
};
Expected by_definition(const std::vector<std::uint8_t>& bytes, std::size_t start,
                       std::size_t length) {
  Expected e;
  for (std::size_t i = 0; i < length; ++i) {
    e.crc = crc16_update(e.crc, bytes[start + i]);
    if (e.crc == 0 && i + 1 >= kMinAdu) e.zeros.push_back(i + 1);
  }
  return e;
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

TEST(CrcScan, FourSideBySideAreEachTheByteAtATimeScanFromAnyState) {
  std::mt19937 rng(20261201);
  const std::vector<std::uint8_t> bytes = frames_back_to_back(rng, 4000);
  std::size_t zeros_seen = 0;
  for (int round = 0; round < 2000; ++round) {
    const std::size_t first = rng() % 3000;
    std::array<CrcScan, 4> scans{};
    std::array<CrcScan*, 4> pointers{};
    std::array<const std::uint8_t*, 4> from{};
    std::array<std::size_t, 4> counts{};
    std::array<std::size_t, 4> before{};
    for (std::size_t k = 0; k < 4; ++k) {
      // Some scans start fresh, others have covered some bytes already (one by one).
      before[k] = rng() % 3 == 0 ? 0 : rng() % 40;
      scans[k].extend(bytes.data() + first + k, before[k]);
      pointers[k] = &scans[k];
      from[k] = bytes.data() + first + k + before[k];
      counts[k] = rng() % 200;
    }
    extend_side_by_side(from, pointers, counts);
    for (std::size_t k = 0; k < 4; ++k) {
      const std::size_t length = before[k] + counts[k];
      const Expected e = by_definition(bytes, first + k, length);
      ASSERT_EQ(scans[k].scanned, length) << "round " << round << " scan " << k;
      ASSERT_EQ(scans[k].crc, e.crc) << "round " << round << " scan " << k;
      ASSERT_EQ(zeros_of(scans[k]), e.zeros) << "round " << round << " scan " << k;
      ASSERT_EQ(scans[k].found_zero, !e.zeros.empty());
      zeros_seen += e.zeros.size();
    }
  }
  EXPECT_GT(zeros_seen, 500U) << "the bytes must give the zero tests work";
}

TEST(CrcScan, ZerosShorterThanTheSmallestFrameAreNotLengths) {
  // Two bytes whose CRC is zero: not a frame (fewer than four bytes), so not a length.
  std::vector<std::uint8_t> bytes;
  for (unsigned v = 0; v <= 0xFFFFU && bytes.empty(); ++v) {
    const std::vector<std::uint8_t> two = {static_cast<std::uint8_t>(v >> 8U),
                                           static_cast<std::uint8_t>(v & 0xFFU)};
    if (crc16(two) == 0) bytes = two;
  }
  ASSERT_EQ(bytes.size(), 2U);
  for (int i = 0; i < 40; ++i) bytes.push_back(static_cast<std::uint8_t>(i * 37));
  std::array<CrcScan, 4> scans{};
  std::array<CrcScan*, 4> pointers{&scans[0], &scans[1], &scans[2], &scans[3]};
  std::array<const std::uint8_t*, 4> from{};
  std::array<std::size_t, 4> counts{};
  for (std::size_t k = 0; k < 4; ++k) {
    from[k] = bytes.data() + k;
    counts[k] = bytes.size() - k;
  }
  extend_side_by_side(from, pointers, counts);
  const std::vector<std::size_t> zeros = zeros_of(scans[0]);
  EXPECT_EQ(std::count(zeros.begin(), zeros.end(), 2U), 0);
  EXPECT_EQ(zeros, by_definition(bytes, 0, bytes.size()).zeros);
  for (std::size_t k = 1; k < 4; ++k) {
    EXPECT_EQ(zeros_of(scans[k]), by_definition(bytes, k, bytes.size() - k).zeros) << k;
  }
}

}  // namespace
}  // namespace rtu
