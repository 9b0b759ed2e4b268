#include "core/time_format.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace rtu
