#include "capture/decimal_time.hpp"

#include <gtest/gtest.h>

namespace rtu {
namespace {

Nanos seconds_ok(std::string_view text, bool exponent = true) {
  const ParsedTime t = parse_decimal_seconds(text, exponent);
  EXPECT_TRUE(t.ok()) << text;
  return t.ns;
}

TEST(DecimalTime, ExponentsShiftTheDecimalPointExactly) {
  EXPECT_EQ(seconds_ok("8.2464e-05"), 82'464);
  EXPECT_EQ(seconds_ok("1.5E3"), 1'500 * kNanosPerSecond);
  EXPECT_EQ(seconds_ok("5e-10"), 1);  // half a nanosecond rounds away from zero
  EXPECT_EQ(seconds_ok("-5e-10"), -1);
  EXPECT_EQ(seconds_ok("4.9e-10"), 0);
  EXPECT_EQ(seconds_ok("1e-400"), 0);
  EXPECT_EQ(seconds_ok("0.000000000000000000000000001e27"), kNanosPerSecond);
  EXPECT_EQ(parse_decimal_seconds("8.2464e-05", true).decimals, 9);
}

TEST(DecimalTime, LargestTimesFitAndLargerOnesAreOutOfRange) {
  EXPECT_EQ(seconds_ok("9223372036.854775807"), std::numeric_limits<Nanos>::max());
  EXPECT_EQ(seconds_ok("-9223372036.854775807"), -std::numeric_limits<Nanos>::max());
  EXPECT_EQ(parse_decimal_seconds("9223372036.854775808", false).status,
            ParsedTime::Status::kOutOfRange);
  EXPECT_EQ(parse_decimal_seconds("9223372036.8547758075", false).status,
            ParsedTime::Status::kOutOfRange);  // rounds up past the maximum
  EXPECT_EQ(parse_decimal_seconds("1e10", true).status, ParsedTime::Status::kOutOfRange);
  EXPECT_EQ(seconds_ok("0000000000000000000000000001.5", false), 1'500'000'000);
}

TEST(DecimalTime, SyntaxErrors) {
  for (const char* bad : {"", "-", ".", "1..2", "1e", "1e+", "1e5", " 1", "1 ", "0x10", "1,5"}) {
    EXPECT_EQ(parse_decimal_seconds(bad, std::string_view(bad) != "1e5").status,
              ParsedTime::Status::kSyntax)
        << bad;
  }
}

TEST(DecimalTime, Iso8601) {
  EXPECT_EQ(parse_iso8601("1970-01-01T00:00:00Z").ns, 0);
  EXPECT_EQ(parse_iso8601("1969-12-31T23:59:59.5+00:00").ns, -500'000'000);
  EXPECT_EQ(parse_iso8601("2000-03-01 00:00:00").ns, 951'868'800 * kNanosPerSecond);
  EXPECT_EQ(parse_iso8601("2022-06-29T04:05:27.591152100-0130").ns,
            1'656'475'527'591'152'100 + 90 * 60 * kNanosPerSecond);
  EXPECT_EQ(parse_iso8601("2022-06-29T04:05:27.5911521004").ns, 1'656'475'527'591'152'100);
  EXPECT_EQ(parse_iso8601("2022-06-29T04:05:27.123456").decimals, 6);
  for (const char* bad :
       {"2022-13-01T00:00:00Z", "2023-02-29T00:00:00Z", "2022-06-29", "2022-06-29T24:00:00Z",
        "2022-06-29T04:05:27.Z", "2022-06-29T04:05:27+1"}) {
    EXPECT_FALSE(parse_iso8601(bad).ok()) << bad;
  }
}

TEST(DecimalTime, StepForDecimals) {
  EXPECT_EQ(step_for_decimals(0), kNanosPerSecond);
  EXPECT_EQ(step_for_decimals(3), kNanosPerMilli);
  EXPECT_EQ(step_for_decimals(6), kNanosPerMicro);
  EXPECT_EQ(step_for_decimals(9), 1);
  EXPECT_EQ(step_for_decimals(15), 1);
}

}  // namespace
}  // namespace rtu
