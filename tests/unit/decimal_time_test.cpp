#include "capture/decimal_time.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

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

// Plain times ("1700000000.123456") take a fast path; "e0" sends the same text through the
// general digit-by-digit parser, which must agree on every value and decimal count.
TEST(DecimalTime, PlainTimesEqualTheGeneralParser) {
  std::uint64_t state = 12345;
  auto next = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return state >> 33U;
  };
  std::vector<std::string> texts = {"0",
                                    "0.0",
                                    "5.",
                                    ".5",
                                    "9999999999.999999999",
                                    "9223372035.999999999",
                                    "9223372036.854775807",
                                    "0000000001.000000001"};
  for (int i = 0; i < 20000; ++i) {
    std::string whole = std::to_string(next() % 10'000'000'000ULL).substr(0, 1 + next() % 10);
    std::string text = next() % 8 == 0 ? "" : whole;
    const auto decimals = static_cast<std::size_t>(next() % 10);
    if (decimals > 0 || next() % 4 == 0) text += '.';
    for (std::size_t d = 0; d < decimals; ++d) text += static_cast<char>('0' + next() % 10);
    texts.push_back(text);
  }
  for (const std::string& text : texts) {
    const ParsedTime plain = parse_decimal_seconds(text, false);
    const ParsedTime general = parse_decimal_seconds(text + "e0", true);
    EXPECT_EQ(plain.status, general.status) << text;
    EXPECT_EQ(plain.ns, general.ns) << text;
    EXPECT_EQ(plain.decimals, general.decimals) << text;
  }
}

// The one-pass word reader of text captures: the same value as the whole-word parser where
// it answers, the word's length, and 0 (leave it to the general parser) for anything else.
TEST(DecimalTime, PlainSecondsWordMatchesTheWordParsedWhole) {
  struct Case {
    std::string_view line;
    std::size_t length;  // 0: not a plain word
  };
  const Case cases[] = {{"0.000572916 01", 11},
                        {"12.5\t03", 4},
                        {"7#comment", 1},
                        {"1700000000.123456", 17},
                        {"5. 01", 2},
                        {".5 01", 2},
                        {"1e3 01", 0},
                        {"-1.5 01", 0},
                        {"1.5x 01", 0},
                        {"1.2.3 01", 0},
                        {" 1.5", 0},
                        {"", 0},
                        {".", 0},
                        {"12345678901 01", 0},
                        {"1.0000000001 01", 0},
                        {"9223372036.854775808 01", 0}};
  for (const Case& c : cases) {
    ParsedTime word;
    word.ns = 42;
    const std::size_t length = parse_plain_seconds_word(c.line, word);
    EXPECT_EQ(length, c.length) << c.line;
    if (length == 0) {
      EXPECT_EQ(word.ns, 42) << "left untouched: " << c.line;
      continue;
    }
    const ParsedTime whole = parse_decimal_seconds(c.line.substr(0, length), false);
    EXPECT_TRUE(whole.ok()) << c.line;
    EXPECT_EQ(word.ns, whole.ns) << c.line;
    EXPECT_EQ(word.decimals, whole.decimals) << c.line;
  }
}

// The plain-word scan reads digits eight at a time; this compares it, on random lines of
// digits, points and separators, with the rule written one character at a time, and its
// values with the general parser's (reached through an exponent, which the scan refuses).
TEST(DecimalTime, PlainSecondsWordAgreesWithACharacterByCharacterReading) {
  const auto expected_length = [](std::string_view line) -> std::size_t {
    std::size_t i = 0;
    while (i < line.size() && line[i] >= '0' && line[i] <= '9') ++i;
    const std::size_t whole = i;
    std::size_t fraction = 0;
    if (i < line.size() && line[i] == '.') {
      ++i;
      while (i < line.size() && line[i] >= '0' && line[i] <= '9') ++i, ++fraction;
    }
    if (whole > 10 || fraction > 9 || whole + fraction == 0) return 0;
    if (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '#') return 0;
    // Ten whole digits may pass int64 ns; the general parser decides those.
    const ParsedTime t = parse_decimal_seconds(std::string(line.substr(0, i)) + "e0", true);
    return t.ok() ? i : 0;
  };
  std::mt19937 random(7);
  // ':' and '/' sit just above and below the digits; '\xb9' is a digit with its top bit set.
  const std::string_view alphabet = "0123456789012345678901234567890123456789.. x#:/\xb9\xff";
  std::size_t plain = 0;
  for (int n = 0; n < 200000; ++n) {
    std::string line(random() % 28, ' ');
    for (char& c : line) c = alphabet[random() % alphabet.size()];
    ParsedTime word;
    const std::size_t length = parse_plain_seconds_word(line, word);
    ASSERT_EQ(length, expected_length(line)) << line;
    if (length == 0) continue;
    ++plain;
    const ParsedTime reference =
        parse_decimal_seconds(line.substr(0, length) + "e0", /*allow_exponent=*/true);
    ASSERT_EQ(word.ns, reference.ns) << line;
    ASSERT_EQ(word.decimals, reference.decimals) << line;
  }
  EXPECT_GT(plain, 10000U);  // the lines exercised the scan, not only its refusals
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
