#include "core/time_format.hpp"

#include <array>
#include <cstdint>
#include <cstring>
#include <iterator>

#include "core/digit_pairs.hpp"

namespace rtu {
namespace {

constexpr std::array<Nanos, 10> kPow10 = {1,      10,      100,      1000,      10000,
                                          100000, 1000000, 10000000, 100000000, 1000000000};

void append_fixed(fmt::memory_buffer& out, Nanos value, Nanos unit, int decimals) {
  // value / unit with `decimals` digits, floor rounding, without overflow for any int64.
  Nanos whole = value / unit;
  Nanos rest = value % unit;
  if (rest < 0) {
    rest += unit;
    --whole;
  }
  const Nanos scale = unit / kPow10[static_cast<std::size_t>(decimals)];
  const Nanos frac = rest / scale;
  if (whole < 0 && frac != 0) {
    // e.g. -0.25 s: floor gives whole=-1, frac=0.75; print as -0.25 instead.
    const Nanos neg_rest = unit - rest;
    fmt::format_to(fmt::appender(out), "-{}.{:0{}d}", -(whole + 1), neg_rest / scale, decimals);
    return;
  }
  // Every record's time goes through here: digits are written directly, not through a
  // format string.
  const fmt::format_int whole_digits(whole);
  const std::size_t at = out.size();
  const auto fraction_size = decimals == 0 ? 0U : static_cast<std::size_t>(decimals) + 1U;
  out.resize(at + whole_digits.size() + fraction_size);
  char* p = out.data() + at;
  std::memcpy(p, whole_digits.data(), whole_digits.size());
  if (decimals == 0) return;
  p += whole_digits.size();
  *p = '.';
  // The fraction's digits from the last, two at a time from a table (half the divisions).
  auto rest_digits = static_cast<std::uint64_t>(frac);  // < 10^decimals
  int i = decimals;
  for (; i >= 2; i -= 2) {
    std::memcpy(p + i - 1, decimal_pair(rest_digits % 100), 2);
    rest_digits /= 100;
  }
  if (i == 1) p[1] = static_cast<char>('0' + rest_digits);
}

}  // namespace

void append_seconds(fmt::memory_buffer& out, Nanos t, int decimals) {
  append_fixed(out, t, kNanosPerSecond, decimals < 0 ? 0 : (decimals > 9 ? 9 : decimals));
}

void append_millis(fmt::memory_buffer& out, Nanos t) {
  append_fixed(out, t, kNanosPerMilli, 3);
}

void append_utc_date(fmt::memory_buffer& out, Nanos t) {
  // Civil date from a day count (Howard Hinnant's days_from_civil, inverted).
  const Nanos z = utc_day(t) + 719468;
  const Nanos era = (z >= 0 ? z : z - 146096) / 146097;
  const Nanos doe = z - era * 146097;
  const Nanos yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const Nanos doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const Nanos mp = (5 * doy + 2) / 153;
  const Nanos day = doy - (153 * mp + 2) / 5 + 1;
  const Nanos month = mp < 10 ? mp + 3 : mp - 9;
  const Nanos year = yoe + era * 400 + (month <= 2 ? 1 : 0);
  fmt::format_to(fmt::appender(out), "{:04}-{:02}-{:02}", year, month, day);
}

void append_utc_time_of_day(fmt::memory_buffer& out, Nanos t, int decimals) {
  constexpr Nanos kDay = 86'400 * kNanosPerSecond;
  const Nanos in_day = t - utc_day(t) * kDay;
  const Nanos seconds = in_day / kNanosPerSecond;
  fmt::format_to(fmt::appender(out), "{:02}:{:02}:", seconds / 3600, seconds / 60 % 60);
  fmt::memory_buffer s;
  append_seconds(s, in_day % (60 * kNanosPerSecond), decimals);
  if (in_day % (60 * kNanosPerSecond) < 10 * kNanosPerSecond) out.push_back('0');
  out.append(s);
}

}  // namespace rtu
