#pragma once
// Exact text → time conversion for capture readers. Times are parsed digit by digit into
// int64 nanoseconds, never through a double, so "1700000000.123456789" keeps every digit.
#include <cstdint>
#include <string_view>

#include "core/time.hpp"

namespace rtu {

struct ParsedTime {
  enum class Status : std::uint8_t { kOk, kSyntax, kOutOfRange };
  Status status = Status::kSyntax;
  Nanos ns = 0;
  // Digits after the decimal point as written (an exponent shifts them: "8.2464e-05" has 9).
  // Says how fine a step the writer used; see step_for_decimals().
  int decimals = 0;
  [[nodiscard]] bool ok() const { return status == Status::kOk; }
};

// Decimal seconds: optional sign, digits, optional '.' and fraction digits (at least one
// digit in all), and with `allow_exponent` an optional e/E exponent. Digits beyond the
// nanosecond are rounded half away from zero. The result is never kUnknownTime: values
// whose magnitude does not fit int64 nanoseconds (about ±292 years) are kOutOfRange.
ParsedTime parse_decimal_seconds(std::string_view text, bool allow_exponent);

// The common case of a timestamp word, in one pass: when `text` starts with plain decimal
// seconds ("1700000000.123456": digits, an optional fraction, at most 10 + 9 digits) ended by
// a blank, '#' or the end of the text, sets `out` as parse_decimal_seconds would and returns
// the word's length. Else returns 0, and the caller cuts the word and parses it as above
// (which also says what is wrong with it).
std::size_t parse_plain_seconds_word(std::string_view text, ParsedTime& out);

// ISO 8601 date and time, "2022-06-29T04:05:27.591152100+00:00" ('T' or ' ' between date and
// time; fraction optional; offset "Z", "+HH:MM", "-HH:MM", "+HHMM" or none, meaning UTC),
// as nanoseconds since 1970-01-01T00:00:00Z.
ParsedTime parse_iso8601(std::string_view text);

// The step a time written with `decimals` decimals implies: 0 → 1 s, 3 → 1 ms, ≥ 9 → 1 ns.
Nanos step_for_decimals(int decimals);

}  // namespace rtu
