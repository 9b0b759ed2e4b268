#pragma once
// The one-pass reading of plain decimal seconds ("1700000000.123456"), the timestamp of
// nearly every line of a text capture. Inline, so that a reader's loop over its lines keeps
// it in place (parse_plain_seconds_word in decimal_time.hpp is the same for other callers).
#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <string_view>

#include "core/byte_words.hpp"
#include "core/time.hpp"

namespace rtu {
namespace plain_seconds_detail {

inline bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

using byte_words::kOnes;

// Eight characters at `p` as one word, the first in its lowest byte, each minus '0': a digit's
// byte holds its value.
inline std::uint64_t digit_word(const char* p) {
  return byte_words::load(p) - 0x30 * kOnes;
}

// How many of digit_word()'s eight characters, from the first, are decimal digits. A byte is
// one when it is below 10 (adding 0x76 keeps its top bit clear) and did not borrow (its top
// bit is clear). A borrow or carry only reaches the bytes after the first non-digit, which do
// not count.
inline unsigned leading_digits(std::uint64_t digits) {
  const std::uint64_t non_digits = (digits | (digits + 0x76 * kOnes)) & byte_words::kHighBits;
  return non_digits == 0 ? 8U : static_cast<unsigned>(std::countr_zero(non_digits)) / 8U;
}

// The value of the digits of a word whose bytes each hold a digit's value (0-9), the first
// character in the lowest byte; bytes before the digits hold 0. Combined pairs, then quads,
// then whole, instead of by a dependent multiply-add per digit.
inline std::uint64_t digits_value(std::uint64_t d) {
  const std::uint64_t pairs = (d * 10 + (d >> 8)) & 0x00FF00FF00FF00FFULL;
  const std::uint64_t quads = (pairs * 100 + (pairs >> 16)) & 0x0000FFFF0000FFFFULL;
  return (quads * 10000 + (quads >> 32)) & 0xFFFFFFFFULL;
}

// The value of the first `count` (0-8) digits of digit_word(): moved to the top of the word,
// zeros before them.
inline std::uint64_t leading_value(std::uint64_t digits, unsigned count) {
  if (count == 0) return 0;
  return digits_value(digits << (8U * (8U - count)));
}

// Reads the run of digits at text[i...] into `value` and `count` (both 0 before), moving `i`
// past it; false when the run is longer than `max`. Eight at a time where eight characters
// are left, then one at a time.
inline bool read_digits(std::string_view text, std::size_t& i, std::uint64_t& value,
                        std::size_t& count, std::size_t max) {
  if (text.size() - i >= 8) {
    const std::uint64_t digits = digit_word(text.data() + i);
    const unsigned run = leading_digits(digits);
    value = leading_value(digits, run);
    count = run;
    i += run;
    if (run < 8) return true;
  }
  while (i < text.size() && is_digit(text[i])) {
    value = value * 10U + static_cast<unsigned>(text[i] - '0');
    if (++count > max) return false;
    ++i;
  }
  return true;
}

inline constexpr std::array<std::uint64_t, 10> kPowersOf10 = {
    1, 10, 100, 1'000, 10'000, 100'000, 1'000'000, 10'000'000, 100'000'000, 1'000'000'000};

}  // namespace plain_seconds_detail

// The shape nearly every capture writes, "1700000000.123456": no sign, no exponent, at most
// 10 whole and 9 fraction digits, so the value fits int64 ns without rounding. Reads it
// from the start of `text` up to the first character that cannot continue it, and returns
// how many characters that was; 0 (and `ns`, `decimals` untouched) when they are not that
// shape. Plain scalars out, not a ParsedTime: a struct written field by field and then copied
// whole stalls on the copy, once per line of a text capture.
inline std::size_t scan_plain_seconds(std::string_view text, Nanos& ns_out, int& decimals_out) {
  constexpr std::size_t kMaxWhole = 10;
  constexpr std::size_t kMaxFraction = 9;
  std::size_t i = 0;
  std::uint64_t whole = 0;
  std::size_t whole_digits = 0;
  if (!plain_seconds_detail::read_digits(text, i, whole, whole_digits, kMaxWhole)) return 0;
  std::uint64_t fraction = 0;
  std::size_t fraction_digits = 0;
  if (i < text.size() && text[i] == '.') {
    ++i;
    if (!plain_seconds_detail::read_digits(text, i, fraction, fraction_digits, kMaxFraction))
      return 0;
  }
  if (whole_digits + fraction_digits == 0) return 0;
  fraction *= plain_seconds_detail::kPowersOf10[kMaxFraction - fraction_digits];
  // Ten whole digits can pass int64 ns (9223372036.854775808): the general parser says so.
  const std::uint64_t ns = whole * 1'000'000'000U + fraction;
  if (ns > std::uint64_t{std::numeric_limits<Nanos>::max()}) return 0;
  ns_out = static_cast<Nanos>(ns);
  decimals_out = static_cast<int>(fraction_digits);
  return i;
}

}  // namespace rtu
