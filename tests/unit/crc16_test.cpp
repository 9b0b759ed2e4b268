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

TEST(Crc16, TooShortIsNeverValid) {
  const std::vector<std::uint8_t> two = {0xFF, 0xFF};
  EXPECT_FALSE(crc16_valid(two));
}

}  // namespace
}  // namespace rtu
