#pragma once
// std::round (halves away from zero) without a call into the maths library: every decoded
// register value is rounded to its point's decimals, and without SSE4.1 the compiler cannot
// inline std::round. Gives exactly what std::round gives, the sign of a zero result included.
#include <cmath>
#include <cstdint>

namespace rtu {

inline double round_half_away(double x) {
  // From 2^52 on every double is an integer; infinities and NaN are not numbers to round.
  if (!(std::fabs(x) < 0x1p52)) return std::round(x);
  const auto whole = static_cast<std::int64_t>(x);         // toward zero
  const double fraction = x - static_cast<double>(whole);  // exact below 2^52
  std::int64_t rounded = whole;
  if (fraction >= 0.5) {
    ++rounded;
  } else if (fraction <= -0.5) {
    --rounded;
  }
  return rounded == 0 ? std::copysign(0.0, x) : static_cast<double>(rounded);
}

}  // namespace rtu
