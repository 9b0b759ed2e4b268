#include "framing/crc_chain.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "bus_builder.hpp"

namespace rtu {
namespace {

using test::with_crc;

std::vector<std::uint8_t> joined(std::initializer_list<std::vector<std::uint8_t>> parts) {
  std::vector<std::uint8_t> out;
  for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
  return out;
}

const std::vector<std::uint8_t> kRequest = with_crc({0x07, 0x41, 0x10, 0x20, 0x30, 0x40});
const std::vector<std::uint8_t> kAnswer = with_crc({0x07, 0x41, 0x01, 0x02, 0x03, 0x04, 0x05});

TEST(CrcChain, TwoFramesBackToBackAreAChain) {
  EXPECT_TRUE(holds_crc_chain(joined({kRequest, kAnswer})));
}

TEST(CrcChain, ChainBehindDamagedBytesIsFound) {
  const std::vector<std::uint8_t> damaged = {0x41, 0x71, 0x38, 0x00, 0x6D};
  EXPECT_TRUE(holds_crc_chain(joined({damaged, kRequest, kAnswer})));
  EXPECT_TRUE(holds_crc_chain(joined({damaged, kRequest, kAnswer, damaged})));
}

TEST(CrcChain, OneFrameIsNoChainEvenWhenItIsTheWhole) {
  EXPECT_FALSE(holds_crc_chain(kAnswer));
  const std::vector<std::uint8_t> damaged = {0x41, 0x71, 0x38, 0x00, 0x6D};
  EXPECT_FALSE(holds_crc_chain(joined({damaged, kAnswer})));
  EXPECT_FALSE(holds_crc_chain(joined({kAnswer, damaged})));
}

TEST(CrcChain, TwoFramesApartAreNoChain) {
  EXPECT_FALSE(holds_crc_chain(joined({kRequest, {0x55}, kAnswer})));
}

// Real frames hold no chain by chance: CRC-valid frames of every length a vendor answer
// has, with varied bytes.
TEST(CrcChain, RealFramesHoldNone) {
  for (std::size_t data = 2; data < 80; ++data) {
    std::vector<std::uint8_t> body = {0x07, 0x41};
    for (std::size_t i = 0; i < data; ++i) {
      body.push_back(static_cast<std::uint8_t>(data * 37 + i * 101));
    }
    EXPECT_FALSE(holds_crc_chain(with_crc(body))) << data;
  }
}

TEST(CrcChain, TooShortForTwoFrames) {
  EXPECT_FALSE(holds_crc_chain(std::vector<std::uint8_t>(7, 0x00)));
  // Eight bytes 00 are no frames either: the CRC from 0xFFFF never comes out zero on them.
  EXPECT_FALSE(holds_crc_chain(std::vector<std::uint8_t>(8, 0x00)));
}

}  // namespace
}  // namespace rtu
