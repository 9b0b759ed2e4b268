#include "serial/mark_decoder.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace rtu {
namespace {

struct Decoded {
  std::vector<std::uint8_t> bytes;
  std::vector<std::uint8_t> errors;
};

// Decodes `raw` split into two reads at `split`.
Decoded decode_split(const std::vector<std::uint8_t>& raw, std::size_t split,
                     std::uint8_t flag = kParityError) {
  MarkDecoder decoder(flag);
  Decoded out;
  decoder.decode({raw.data(), split}, out.bytes, out.errors);
  decoder.decode({raw.data() + split, raw.size() - split}, out.bytes, out.errors);
  EXPECT_FALSE(decoder.pending());
  return out;
}

// Raw stream: 01, FF FF (data FF), FF 00 55 (parity error on 55), 02, FF 00 00 (break), 03.
const std::vector<std::uint8_t> kRaw = {0x01, 0xFF, 0xFF, 0xFF, 0x00, 0x55,
                                        0x02, 0xFF, 0x00, 0x00, 0x03};
const std::vector<std::uint8_t> kBytes = {0x01, 0xFF, 0x55, 0x02, 0x00, 0x03};
const std::vector<std::uint8_t> kErrors = {kLineOk, kLineOk, kParityError,
                                           kLineOk, kBreak,  kLineOk};

TEST(MarkDecoder, DecodesEveryMarkKind) {
  const auto out = decode_split(kRaw, kRaw.size());
  EXPECT_EQ(out.bytes, kBytes);
  EXPECT_EQ(out.errors, kErrors);
}

TEST(MarkDecoder, MarksSplitAtEveryPositionKeepTheirMeaning) {
  for (std::size_t split = 0; split <= kRaw.size(); ++split) {
    SCOPED_TRACE(split);
    const auto out = decode_split(kRaw, split);
    EXPECT_EQ(out.bytes, kBytes);
    EXPECT_EQ(out.errors, kErrors);
  }
}

TEST(MarkDecoder, EveryByteInItsOwnRead) {
  MarkDecoder decoder;
  Decoded out;
  for (const auto b : kRaw) {
    decoder.decode({&b, 1}, out.bytes, out.errors);
  }
  EXPECT_EQ(out.bytes, kBytes);
  EXPECT_EQ(out.errors, kErrors);
}

TEST(MarkDecoder, UnfinishedMarkIsHeldUntilItsEnd) {
  MarkDecoder decoder;
  Decoded out;
  const std::vector<std::uint8_t> first = {0x10, 0xFF};
  decoder.decode(first, out.bytes, out.errors);
  EXPECT_TRUE(decoder.pending());
  EXPECT_EQ(out.bytes, std::vector<std::uint8_t>({0x10}));
  const std::vector<std::uint8_t> second = {0x00};
  decoder.decode(second, out.bytes, out.errors);
  EXPECT_TRUE(decoder.pending());
  EXPECT_EQ(out.bytes.size(), 1U);
  const std::vector<std::uint8_t> third = {0x7E};
  decoder.decode(third, out.bytes, out.errors);
  EXPECT_FALSE(decoder.pending());
  EXPECT_EQ(out.bytes, std::vector<std::uint8_t>({0x10, 0x7E}));
  EXPECT_EQ(out.errors, std::vector<std::uint8_t>({kLineOk, kParityError}));
}

TEST(MarkDecoder, ErrorFlagFollowsTheLine) {
  const std::vector<std::uint8_t> raw = {0xFF, 0x00, 0x42};
  const auto out = decode_split(raw, 1, kFramingError);
  EXPECT_EQ(out.bytes, std::vector<std::uint8_t>({0x42}));
  EXPECT_EQ(out.errors, std::vector<std::uint8_t>({kFramingError}));
}

TEST(MarkDecoder, RunsOfFFAndMarksBackToBack) {
  // FF FF FF FF = two data FF; FF 00 FF = error on FF; FF 00 00 twice = two breaks.
  const std::vector<std::uint8_t> raw = {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x00, 0xFF,
                                         0xFF, 0x00, 0x00, 0xFF, 0x00, 0x00};
  for (std::size_t split = 0; split <= raw.size(); ++split) {
    SCOPED_TRACE(split);
    const auto out = decode_split(raw, split);
    EXPECT_EQ(out.bytes, std::vector<std::uint8_t>({0xFF, 0xFF, 0xFF, 0x00, 0x00}));
    EXPECT_EQ(out.errors,
              std::vector<std::uint8_t>({kLineOk, kLineOk, kParityError, kBreak, kBreak}));
  }
}

}  // namespace
}  // namespace rtu
