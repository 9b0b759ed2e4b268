#include "core/time_format.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>

namespace rtu {
namespace {

std::string utc_text(Nanos t) {
  fmt::memory_buffer out;
  append_utc_date(out, t);
  out.push_back(' ');
  append_utc_time_of_day(out, t, 6);
  return {out.data(), out.size()};
}

TEST(UtcTime, DatesAndTimesOfDay) {
  // 2026-11-23 08:43:45.4206471 UTC = 1795423425.4206471 s since 1970.
  EXPECT_EQ(utc_text(1'795'423'425'420'647'100), "2026-11-23 08:43:45.420647");
  EXPECT_EQ(utc_text(0), "1970-01-01 00:00:00.000000");
  // Leap day and the last nanosecond of a day.
  EXPECT_EQ(utc_text(1'709'251'199'999'999'999), "2024-02-29 23:59:59.999999");
  EXPECT_EQ(utc_text(951'782'400 * kNanosPerSecond), "2000-02-29 00:00:00.000000");
  EXPECT_EQ(utc_day(86'400 * kNanosPerSecond - 1), 0);
  EXPECT_EQ(utc_day(-1), -1);
}

std::string seconds_text(Nanos t, int decimals) {
  fmt::memory_buffer out;
  append_seconds(out, t, decimals);
  return {out.data(), out.size()};
}

TEST(SecondsText, DigitsAsWrittenWithFloorRounding) {
  EXPECT_EQ(seconds_text(1'700'000'000'123'456'789, 6), "1700000000.123456");
  EXPECT_EQ(seconds_text(1'700'000'000'123'456'789, 9), "1700000000.123456789");
  EXPECT_EQ(seconds_text(1'700'000'000'123'456'789, 0), "1700000000");
  EXPECT_EQ(seconds_text(0, 9), "0.000000000");
  EXPECT_EQ(seconds_text(7, 9), "0.000000007");
  EXPECT_EQ(seconds_text(1'000'000'000, 1), "1.0");
  EXPECT_EQ(seconds_text(-250'000'000, 3), "-0.250");
  EXPECT_EQ(seconds_text(-1, 9), "-0.000000001");
  EXPECT_EQ(seconds_text(-1'500'000'000, 1), "-1.5");
  EXPECT_EQ(seconds_text(-2'000'000'000, 3), "-2.000");
  EXPECT_EQ(seconds_text(std::numeric_limits<Nanos>::max(), 9), "9223372036.854775807");
  EXPECT_EQ(seconds_text(std::numeric_limits<Nanos>::min(), 9), "-9223372036.854775808");
  EXPECT_EQ(seconds_text(123'456'789'012, 20), "123.456789012");  // at most 9 decimals
  EXPECT_EQ(seconds_text(123'456'789'012, -1), "123");
}

}  // namespace
}  // namespace rtu
