#include "core/bucket_index.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace rtu {
namespace {

// The shapes of the capture histograms' formulas: 48 buckets an octave from 1 µs (the byte
// spacings), 4 an octave of µs + 1 (the read intervals), and one that skips buckets.
std::size_t spacing_formula(std::int64_t ns) {
  if (ns < 1000) return 0;
  const auto b = 1 + static_cast<std::size_t>(48.0 * std::log2(static_cast<double>(ns) / 1e3));
  return std::min<std::size_t>(b, 1008);
}
std::size_t interval_formula(std::int64_t ns) {
  const auto b = static_cast<std::size_t>(4.0 * std::log2(static_cast<double>(ns) / 1e3 + 1.0));
  return std::min<std::size_t>(b, 159);
}
std::size_t skipping_formula(std::int64_t ns) {
  return ns < 10 ? 0 : 3 * static_cast<std::size_t>(std::log10(static_cast<double>(ns)));
}

void expect_formula(std::size_t (*formula)(std::int64_t)) {
  const BucketIndex index(BucketIndex::lower_bounds_of(formula));
  std::vector<std::int64_t> values = {0, 1, 2, 127, 128, 129, 255, 256, 1000, 999, 1001};
  for (std::size_t b = 1; b < index.buckets(); ++b) {
    values.push_back(index.lower(b));
    values.push_back(index.lower(b) - 1);
    values.push_back(index.lower(b) + 1);
  }
  std::mt19937_64 rng(7);
  for (int i = 0; i < 20000; ++i) {
    const int bits = static_cast<int>(rng() % 62);
    values.push_back(static_cast<std::int64_t>(rng() >> (64 - bits - 1)));
  }
  values.push_back(std::int64_t{1} << 62);
  values.push_back(INT64_MAX);
  for (const std::int64_t v : values) {
    if (v < 0) continue;
    ASSERT_EQ(index.find(v), formula(std::min<std::int64_t>(v, std::int64_t{1} << 62))) << v;
  }
}

TEST(BucketIndex, GivesTheFormulasBucketAtEveryBoundAndBetween) {
  expect_formula(spacing_formula);
  expect_formula(interval_formula);
  expect_formula(skipping_formula);
}

TEST(BucketIndex, FindsGivenBoundsWhateverTheirWidth) {
  // Buckets one value wide next to very wide ones.
  const std::vector<std::int64_t> lower = {0, 5, 6, 7, 1000, 1001, 1'000'000'000};
  const BucketIndex index(lower);
  for (std::int64_t v = 0; v < 2000; ++v) {
    const auto expected = static_cast<std::size_t>(
        std::upper_bound(lower.begin() + 1, lower.end(), v) - lower.begin() - 1);
    ASSERT_EQ(index.find(v), expected) << v;
  }
  EXPECT_EQ(index.find(999'999'999), 5U);
  EXPECT_EQ(index.find(1'000'000'000), 6U);
  EXPECT_EQ(index.find(INT64_MAX), 6U);
}

}  // namespace
}  // namespace rtu
