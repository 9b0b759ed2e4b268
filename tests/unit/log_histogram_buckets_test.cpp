// LogHistogram::bucket_of looks for a value among the bounds of its octave only; it must give
// the bucket a search of all the bounds gives: at every bound and next to it, at every power
// of two and next to it, and on random values from 0 to the largest duration.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>

#include "report/log_histogram.hpp"

namespace rtu {
namespace {

void expect_same_bucket(Nanos value) {
  ASSERT_EQ(LogHistogram::bucket_of(value), LogHistogram::bucket_by_search(value)) << value;
}

TEST(LogHistogramBuckets, OctaveSearchAgreesWithTheFullSearch) {
  for (int k = 0; k < 63; ++k) {
    const Nanos p = Nanos{1} << k;
    for (const Nanos v : {p - 1, p, p + 1}) expect_same_bucket(v);
  }
  // Every bucket boundary: the first value of each bucket and the one below it.
  Nanos previous = -1;
  std::size_t boundaries = 0;
  for (Nanos v = 0; v < 100'000'000; v += 1 + v / 4096) {
    const std::size_t b = LogHistogram::bucket_by_search(v);
    if (previous >= 0 && b != LogHistogram::bucket_by_search(previous)) {
      ++boundaries;
      for (Nanos w = previous; w <= v; ++w) expect_same_bucket(w);
    }
    previous = v;
  }
  EXPECT_GT(boundaries, 400U);
  expect_same_bucket(std::numeric_limits<Nanos>::max());
  expect_same_bucket(std::numeric_limits<Nanos>::min());
  std::mt19937_64 rng(7);
  for (int i = 0; i < 1'000'000; ++i) {
    const int bits = static_cast<int>(rng() % 63);
    expect_same_bucket(static_cast<Nanos>(rng() >> (64 - 1 - bits)) &
                       std::numeric_limits<Nanos>::max());
  }
}

}  // namespace
}  // namespace rtu
