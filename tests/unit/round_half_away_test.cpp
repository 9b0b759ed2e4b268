// round_half_away gives exactly what std::round gives: on halves of both signs, near the
// 2^52 edge, on zeros, infinities and NaN, and on two million random values at scales from
// 10^-6 to 10^20 (bit for bit, so the sign of a zero counts).
#include "core/round_half_away.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace rtu {
namespace {

std::uint64_t bits(double x) {
  return std::bit_cast<std::uint64_t>(x);
}

void expect_same(double x) {
  const double expected = std::round(x);
  const double got = round_half_away(x);
  if (std::isnan(expected)) {
    EXPECT_TRUE(std::isnan(got)) << x;
  } else {
    EXPECT_EQ(bits(got), bits(expected)) << x;
  }
}

TEST(RoundHalfAway, EdgesAgreeWithStdRound) {
  const double edge = 0x1p52;
  const std::vector<double> cases = {0.0,
                                     -0.0,
                                     0.5,
                                     -0.5,
                                     1.5,
                                     -1.5,
                                     2.5,
                                     -2.5,
                                     0.49999999999999994,
                                     -0.49999999999999994,
                                     0.3,
                                     -0.3,
                                     1e-300,
                                     -1e-300,
                                     edge - 0.5,
                                     -(edge - 0.5),
                                     edge - 1.5,
                                     edge,
                                     -edge,
                                     edge + 2,
                                     1e300,
                                     -1e300,
                                     std::numeric_limits<double>::infinity(),
                                     -std::numeric_limits<double>::infinity(),
                                     std::numeric_limits<double>::quiet_NaN(),
                                     std::numeric_limits<double>::denorm_min()};
  for (const double x : cases) expect_same(x);
}

TEST(RoundHalfAway, RandomValuesAgreeWithStdRound) {
  std::mt19937_64 rng(20261201);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-6, 20);
  std::uniform_int_distribution<std::int64_t> raw(-70000, 70000);
  for (int i = 0; i < 1'000'000; ++i) {
    expect_same(unit(rng) * std::pow(10.0, exponent(rng)));
    // The shape decoded registers have: an integer times a decimal scale, back to decimals.
    expect_same(static_cast<double>(raw(rng)) * 0.1 * 10.0 + 0.5 * (i % 2));
  }
}

}  // namespace
}  // namespace rtu
