#include "capture/decimal_time.hpp"

#include <limits>
#include <optional>

#include "capture/plain_seconds.hpp"

namespace rtu {
namespace {

constexpr std::uint64_t kMaxMagnitude = std::numeric_limits<Nanos>::max();
// An exponent beyond this either overflows int64 ns or rounds to zero; capping it keeps
// the digit loops short on hostile input.
constexpr int kMaxExponent = 64;

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

// Appends one decimal digit to `acc`; false when the result would exceed int64.
bool push_digit(std::uint64_t& acc, unsigned digit) {
  if (acc > (kMaxMagnitude - digit) / 10U) return false;
  acc = acc * 10U + digit;
  return true;
}

// Value of the digit string `digits` (the '.' already removed) whose decimal point sits
// after `point` digits, in nanoseconds, rounded half away from zero. False on overflow.
// `digit_at(k)` yields digit k of the string, for k < count.
template <typename DigitAt>
bool scale_to_nanos(DigitAt digit_at, long count, long point, std::uint64_t& out) {
  const long kept = point + 9;  // digits that land at or above the nanosecond
  std::uint64_t acc = 0;
  for (long k = 0; k < kept; ++k) {
    const unsigned d = k < count ? digit_at(k) : 0U;
    if (!push_digit(acc, d)) return false;
  }
  if (kept >= 0 && kept < count && digit_at(kept) >= 5U) {
    if (acc == kMaxMagnitude) return false;
    ++acc;
  }
  out = acc;
  return true;
}

void set_ok(ParsedTime& out, Nanos ns, int decimals) {
  out.status = ParsedTime::Status::kOk;
  out.ns = ns;
  out.decimals = decimals;
}

bool parse_plain_seconds(std::string_view text, ParsedTime& out) {
  Nanos ns = 0;
  int decimals = 0;
  const std::size_t length = scan_plain_seconds(text, ns, decimals);
  if (length == 0 || length != text.size()) return false;  // "" is for the general parser
  set_ok(out, ns, decimals);
  return true;
}

}  // namespace

Nanos step_for_decimals(int decimals) {
  Nanos step = 1;
  for (int d = decimals; d < 9; ++d) step *= 10;
  return step;
}

std::size_t parse_plain_seconds_word(std::string_view text, ParsedTime& out) {
  Nanos ns = 0;
  int decimals = 0;
  const std::size_t length = scan_plain_seconds(text, ns, decimals);
  if (length == 0) return 0;
  if (length < text.size() && text[length] != ' ' && text[length] != '\t' && text[length] != '#') {
    return 0;
  }
  set_ok(out, ns, decimals);
  return length;
}

ParsedTime parse_decimal_seconds(std::string_view text, bool allow_exponent) {
  ParsedTime result;
  if (parse_plain_seconds(text, result)) return result;
  std::size_t i = 0;
  bool negative = false;
  if (i < text.size() && (text[i] == '-' || text[i] == '+')) negative = text[i++] == '-';
  const std::size_t int_begin = i;
  while (i < text.size() && is_digit(text[i])) ++i;
  const std::size_t int_end = i;
  std::size_t frac_begin = i;
  std::size_t frac_end = i;
  if (i < text.size() && text[i] == '.') {
    frac_begin = ++i;
    while (i < text.size() && is_digit(text[i])) ++i;
    frac_end = i;
  }
  const auto int_count = static_cast<long>(int_end - int_begin);
  const auto frac_count = static_cast<long>(frac_end - frac_begin);
  if (int_count + frac_count == 0) return result;
  long exponent = 0;
  if (allow_exponent && i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    bool exp_negative = false;
    if (i < text.size() && (text[i] == '-' || text[i] == '+')) exp_negative = text[i++] == '-';
    const std::size_t exp_begin = i;
    while (i < text.size() && is_digit(text[i])) {
      if (exponent <= kMaxExponent) exponent = exponent * 10 + (text[i] - '0');
      ++i;
    }
    if (i == exp_begin) return result;
    if (exp_negative) exponent = -exponent;
  }
  if (i != text.size()) return result;

  auto digit_at = [&](long k) -> unsigned {
    const std::size_t pos = k < int_count ? int_begin + static_cast<std::size_t>(k)
                                          : frac_begin + static_cast<std::size_t>(k - int_count);
    return static_cast<unsigned>(text[pos] - '0');
  };
  // Leading zeros carry no value; skipping them keeps the loop short for "0000…1".
  long first = 0;
  const long count = int_count + frac_count;
  while (first < count && digit_at(first) == 0U) ++first;
  std::uint64_t magnitude = 0;
  if (first < count) {
    const long point = int_count + exponent - first;
    if (point > 19) {  // ≥ 10^19 s cannot fit whatever the digits
      result.status = ParsedTime::Status::kOutOfRange;
      return result;
    }
    auto shifted = [&](long k) { return digit_at(k + first); };
    if (!scale_to_nanos(shifted, count - first, point, magnitude)) {
      result.status = ParsedTime::Status::kOutOfRange;
      return result;
    }
  }
  result.status = ParsedTime::Status::kOk;
  result.ns = negative ? -static_cast<Nanos>(magnitude) : static_cast<Nanos>(magnitude);
  const long decimals = frac_count - exponent;
  result.decimals = decimals < 0 ? 0 : static_cast<int>(decimals > 99 ? 99 : decimals);
  return result;
}

namespace {

// Reads exactly `n` digits at `pos` into `out`.
bool fixed_digits(std::string_view text, std::size_t& pos, int n, int& out) {
  out = 0;
  for (int k = 0; k < n; ++k, ++pos) {
    if (pos >= text.size() || !is_digit(text[pos])) return false;
    out = out * 10 + (text[pos] - '0');
  }
  return true;
}

bool expect_char(std::string_view text, std::size_t& pos, char c) {
  if (pos >= text.size() || text[pos] != c) return false;
  ++pos;
  return true;
}

bool leap_year(long y) {
  return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
}

int days_in_month(long y, int m) {
  static constexpr int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return m == 2 && leap_year(y) ? 29 : kDays[m - 1];
}

// Days from 1970-01-01 to the given proleptic Gregorian date. Counts whole 400-year cycles
// (146097 days each) from 0000-03-01, so that the leap day falls at the end of a year.
long days_from_civil(long y, int m, int d) {
  if (m <= 2) --y;
  const long cycle = (y >= 0 ? y : y - 399) / 400;
  const long year_of_cycle = y - cycle * 400;                         // 0..399
  const long month_from_march = m > 2 ? m - 3 : m + 9;                // 0..11
  const long day_of_year = (153 * month_from_march + 2) / 5 + d - 1;  // 0..365
  const long day_of_cycle =
      year_of_cycle * 365 + year_of_cycle / 4 - year_of_cycle / 100 + day_of_year;
  constexpr long kDaysFrom0000To1970 = 719468;
  return cycle * 146097 + day_of_cycle - kDaysFrom0000To1970;
}

}  // namespace

ParsedTime parse_iso8601(std::string_view text) {
  ParsedTime result;
  std::size_t pos = 0;
  int year = 0;
  int month = 0;
  int day = 0;
  int hour = 0;
  int minute = 0;
  int second = 0;
  if (!fixed_digits(text, pos, 4, year) || !expect_char(text, pos, '-') ||
      !fixed_digits(text, pos, 2, month) || !expect_char(text, pos, '-') ||
      !fixed_digits(text, pos, 2, day)) {
    return result;
  }
  if (pos >= text.size() || (text[pos] != 'T' && text[pos] != ' ')) return result;
  ++pos;
  if (!fixed_digits(text, pos, 2, hour) || !expect_char(text, pos, ':') ||
      !fixed_digits(text, pos, 2, minute) || !expect_char(text, pos, ':') ||
      !fixed_digits(text, pos, 2, second)) {
    return result;
  }
  if (month < 1 || month > 12 || day < 1 || day > days_in_month(year, month) || hour > 23 ||
      minute > 59 || second > 60) {
    return result;
  }
  std::uint64_t fraction_ns = 0;
  if (pos < text.size() && (text[pos] == '.' || text[pos] == ',')) {
    const std::size_t begin = ++pos;
    while (pos < text.size() && is_digit(text[pos])) ++pos;
    if (pos == begin) return result;
    auto digit_at = [&](long k) {
      return static_cast<unsigned>(text[begin + static_cast<std::size_t>(k)] - '0');
    };
    // A fraction below one second cannot overflow.
    scale_to_nanos(digit_at, static_cast<long>(pos - begin), 0, fraction_ns);
    result.decimals = static_cast<int>(pos - begin > 99 ? 99 : pos - begin);
  }
  long offset_minutes = 0;
  if (pos < text.size()) {
    if (text[pos] == 'Z') {
      ++pos;
    } else if (text[pos] == '+' || text[pos] == '-') {
      const bool behind = text[pos++] == '-';
      int oh = 0;
      int om = 0;
      if (!fixed_digits(text, pos, 2, oh)) return result;
      if (pos < text.size() && text[pos] == ':') ++pos;
      if (!fixed_digits(text, pos, 2, om) || oh > 23 || om > 59) return result;
      offset_minutes = (behind ? -1 : 1) * (oh * 60L + om);
    }
  }
  if (pos != text.size()) return result;
  const long days = days_from_civil(year, month, day);
  const long seconds = days * 86400L + hour * 3600L + minute * 60L + second - offset_minutes * 60L;
  // Four-digit years keep |seconds| below 2.6e11; int64 ns hold ±9.2e9 s.
  constexpr long kMaxSeconds = std::numeric_limits<Nanos>::max() / kNanosPerSecond - 1;
  if (seconds > kMaxSeconds || seconds < -kMaxSeconds) {
    result.status = ParsedTime::Status::kOutOfRange;
    return result;
  }
  result.ns = static_cast<Nanos>(seconds) * kNanosPerSecond + static_cast<Nanos>(fraction_ns);
  result.status = ParsedTime::Status::kOk;
  return result;
}

}  // namespace rtu
