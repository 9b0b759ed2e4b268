#pragma once
// std::round (halves away from zero) without its library call: the device stage rounds every
// decoded value to its point's decimals, and the call through the PLT cost more than the
// rounding. Bit for bit what std::round gives, signed zeros, infinities and NaN included
// (tests/unit/round_half_away_test.cpp compares them).
#include <cmath>
#include <cstdint>

namespace rtu {

inline double round_half_away(double x) {
  // From 2^52 on every double is a whole number; NaN fails the comparison and is returned.
  constexpr double kAllWhole = 4503599627370496.0;
  if (!(std::fabs(x) < kAllWhole)) return x;
  const double whole = static_cast<double>(static_cast<std::int64_t>(x));  // toward zero
  const double rest = x - whole;  // exact: both lie within 2^52 of each other
  if (rest >= 0.5) return whole + 1.0;
  if (rest <= -0.5) return whole - 1.0;
  return std::copysign(whole, x);  // -0.3 rounds to -0.0, as std::round does
}

}  // namespace rtu
