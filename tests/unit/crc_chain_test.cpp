#include "framing/crc_chain.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "bus_builder.hpp"
#include "core/crc16.hpp"
#include "framing/record.hpp"

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

// The definition, asked directly: two CRC-valid spans [a, b) and [b, c) of at least kMinAdu
// bytes each.
bool chain_by_definition(const std::vector<std::uint8_t>& bytes) {
  const std::size_t n = bytes.size();
  const auto valid = [&bytes](std::size_t from, std::size_t to) {
    return to - from >= kMinAdu && crc16({bytes.data() + from, to - from}) == 0;
  };
  for (std::size_t b = kMinAdu; b + kMinAdu <= n; ++b) {
    bool ends_here = false;
    for (std::size_t a = 0; a + kMinAdu <= b && !ends_here; ++a) ends_here = valid(a, b);
    if (!ends_here) continue;
    for (std::size_t c = b + kMinAdu; c <= n; ++c) {
      if (valid(b, c)) return true;
    }
  }
  return false;
}

// Spans of random bytes with frames put in at random places, some back to back and some
// with a bit flipped, up to the longest frame: the check answers as the definition does.
TEST(CrcChain, AnswersAsTheDefinitionOnRandomSpans) {
  std::mt19937 random(20261207);
  int chains = 0;
  int none = 0;
  for (int round = 0; round < 3000; ++round) {
    std::vector<std::uint8_t> span;
    const std::size_t limit = round % 10 == 0 ? kMaxAdu : 64;
    while (span.size() < limit) {
      const auto kind = random() % 3;
      if (kind == 0) {
        span.push_back(static_cast<std::uint8_t>(random()));
        continue;
      }
      std::vector<std::uint8_t> body(2 + random() % 12);
      for (auto& byte : body) byte = static_cast<std::uint8_t>(random());
      auto frame = with_crc(body);
      if (kind == 2)
        frame[random() % frame.size()] ^= static_cast<std::uint8_t>(1U << (random() % 8));
      span.insert(span.end(), frame.begin(), frame.end());
    }
    span.resize(std::min<std::size_t>(span.size(), 1 + random() % limit));
    const bool expected = chain_by_definition(span);
    (expected ? chains : none) += 1;
    ASSERT_EQ(holds_crc_chain(span), expected)
        << "round " << round << ", " << span.size() << " bytes";
  }
  // Both answers were asked for many times.
  EXPECT_GT(chains, 300);
  EXPECT_GT(none, 300);
}

}  // namespace
}  // namespace rtu
