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

// Equal as bits: -0.0 and 0.0 differ here, as they do in a value's text.
void expect_same_as_std(double x) {
  const double ours = round_half_away(x);
  const double theirs = std::round(x);
  if (std::isnan(theirs)) {
    EXPECT_TRUE(std::isnan(ours)) << x;
    return;
  }
  EXPECT_EQ(std::bit_cast<std::uint64_t>(ours), std::bit_cast<std::uint64_t>(theirs))
      << "x = " << x << ": " << ours << " against " << theirs;
}

TEST(RoundHalfAway, EdgeValuesRoundAsStdRoundDoes) {
  const double max = std::numeric_limits<double>::max();
  const double tiny = std::numeric_limits<double>::denorm_min();
  const std::vector<double> edges = {0.0,
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
                                     tiny,
                                     -tiny,
                                     4503599627370495.5,
                                     -4503599627370495.5,
                                     4503599627370496.0,
                                     4503599627370497.0,
                                     9007199254740993.0,
                                     1e300,
                                     -1e300,
                                     max,
                                     -max,
                                     std::numeric_limits<double>::infinity(),
                                     -std::numeric_limits<double>::infinity(),
                                     std::numeric_limits<double>::quiet_NaN()};
  for (const double x : edges) expect_same_as_std(x);
  for (double x = -1000.0; x <= 1000.0; x += 0.25) expect_same_as_std(x);
}

TEST(RoundHalfAway, ScaledRegisterValuesRoundAsStdRoundDoes) {
  // What the device stage rounds: raw values times a scale times a power of ten.
  std::mt19937_64 random(11);
  std::uniform_int_distribution<std::int64_t> raw(-2147483648LL, 4294967295LL);
  const double scales[] = {1.0, 0.1, 0.01, 0.001, 1e-6, 10.0, 0.5, 1.0 / 3.0};
  const double powers[] = {1.0, 10.0, 100.0, 1000.0, 1e6};
  for (int i = 0; i < 200000; ++i) {
    const double value = static_cast<double>(raw(random)) * scales[i % 8];
    expect_same_as_std(value * powers[i % 5]);
    // And any double at all, from its bits.
    expect_same_as_std(std::bit_cast<double>(random()));
  }
}

}  // namespace
}  // namespace rtu
