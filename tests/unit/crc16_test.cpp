#include "core/crc16.hpp"

#include <gtest/gtest.h>

#include <string_view>
#include <vector>

namespace rtu {
namespace {

TEST(Crc16, CheckValueOf123456789) {
  constexpr std::string_view kText = "123456789";
  std::vector<std::uint8_t> bytes(kText.begin(), kText.end());
  EXPECT_EQ(crc16(bytes), 0x4B37);
}

TEST(Crc16, SpecExamplesAppendLowByteFirst) {
  const std::vector<std::uint8_t> adu = {0x11, 0x06, 0x00, 0x01, 0x00, 0x03, 0x9A, 0x9B};
  EXPECT_EQ(crc16(std::span(adu).first(6)), 0x9B9A);
  EXPECT_TRUE(crc16_valid(adu));
}

TEST(Crc16, DetectsSingleBitError) {
  std::vector<std::uint8_t> adu = {0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD};
  EXPECT_TRUE(crc16_valid(adu));
  adu[3] ^= 0x10;
  EXPECT_FALSE(crc16_valid(adu));
}

// The whole-span CRC folds in several bytes at a time: it must be the byte-by-byte CRC for
// every length (all remainders of the eight-byte steps), every starting register, and bytes
// that reach every table entry.
TEST(Crc16, SpanIsTheByteByByteCrcForEveryLengthAndStart) {
  std::vector<std::uint8_t> bytes(300);
  std::uint32_t state = 12345;
  for (auto& b : bytes) {
    state = state * 1103515245U + 12345U;
    b = static_cast<std::uint8_t>(state >> 16U);
  }
  for (const std::uint16_t start :
       {kCrcInit, std::uint16_t{0}, std::uint16_t{0x1234}, std::uint16_t{0xA5F0}}) {
    for (std::size_t offset = 0; offset < 3; ++offset) {
      for (std::size_t len = 0; len + offset <= bytes.size(); ++len) {
        const std::span<const std::uint8_t> span(bytes.data() + offset, len);
        std::uint16_t expected = start;
        for (const std::uint8_t b : span) expected = crc16_update(expected, b);
        ASSERT_EQ(crc16(span, start), expected) << "length " << len << " offset " << offset;
      }
    }
  }
}

TEST(Crc16, TooShortIsNeverValid) {
  const std::vector<std::uint8_t> two = {0xFF, 0xFF};
  EXPECT_FALSE(crc16_valid(two));
}

}  // namespace
}  // namespace rtu
