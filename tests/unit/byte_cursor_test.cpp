#include "core/byte_cursor.hpp"

#include <gtest/gtest.h>

#include <array>

namespace rtu {
namespace {

constexpr std::array<std::uint8_t, 5> kBytes = {0x01, 0x02, 0x03, 0x04, 0x05};

TEST(ByteCursor, ReadsBigEndianFields) {
  ByteCursor cur(kBytes);
  EXPECT_EQ(cur.u8(), 0x01);
  EXPECT_EQ(cur.u16(), 0x0203);
  EXPECT_EQ(cur.position(), 3U);
  EXPECT_EQ(cur.remaining(), 2U);
  EXPECT_TRUE(cur.ok());
  EXPECT_EQ(cur.u16(), 0x0405);
  EXPECT_TRUE(cur.at_end());
  EXPECT_TRUE(cur.ok());
}

TEST(ByteCursor, ReadPastTheEndFailsAndStaysFailed) {
  ByteCursor cur{std::span<const std::uint8_t>(kBytes).first(3)};
  EXPECT_EQ(cur.u16(), 0x0102);
  EXPECT_EQ(cur.u16(), 0);  // one byte left: no partial read
  EXPECT_FALSE(cur.ok());
  EXPECT_TRUE(cur.at_end());
  EXPECT_EQ(cur.u8(), 0);  // later fields never come from shifted bytes
  EXPECT_FALSE(cur.ok());
}

TEST(ByteCursor, TakeClipsAndFails) {
  ByteCursor cur(kBytes);
  EXPECT_EQ(cur.take(2).size(), 2U);
  const auto rest = cur.take(10);
  EXPECT_EQ(rest.size(), 3U);
  EXPECT_EQ(rest[0], 0x03);
  EXPECT_FALSE(cur.ok());
}

TEST(ByteCursor, TakeUpToNeverFails) {
  ByteCursor cur(kBytes);
  EXPECT_EQ(cur.take_up_to(100).size(), 5U);
  EXPECT_TRUE(cur.ok());
  EXPECT_TRUE(cur.rest().empty());
  EXPECT_TRUE(cur.ok());
}

TEST(ByteCursor, EmptySpan) {
  ByteCursor cur;
  EXPECT_TRUE(cur.at_end());
  EXPECT_EQ(cur.u8(), 0);
  EXPECT_FALSE(cur.ok());
}

}  // namespace
}  // namespace rtu
