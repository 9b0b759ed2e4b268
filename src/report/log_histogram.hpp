#pragma once
// A bounded quantile sketch for durations: counts in logarithmic buckets, so its memory is
// fixed at construction whatever the number of samples, and any quantile it returns lies
// within `kRelativeError` of a true sample value of that rank (1 µs absolute below 1 µs).
// The exact minimum, maximum, count and sum are kept beside the buckets.
//
// Quantiles use the nearest-rank definition: q(p) is the sample of 1-based rank
// ceil(p × n) in sorted order (p = 0 gives the minimum).
#include <cstdint>
#include <vector>

#include "core/time.hpp"

namespace rtu {

class LogHistogram {
 public:
  // Bucket i ≥ 1 holds values in [kFloor·γ^(i-1), kFloor·γ^i); bucket 0 everything below
  // kFloor (zero and negative durations included). Values above the top land in the last.
  static constexpr double kGamma = 1.02;
  static constexpr double kRelativeError = 0.01;  // (γ - 1) / (γ + 1), rounded up
  static constexpr Nanos kFloor = kNanosPerMicro;
  static constexpr std::size_t kBuckets = 1400;  // kFloor·γ^1399 ≈ 1 day

  void add(Nanos value);
  void merge(const LogHistogram& other);

  [[nodiscard]] std::uint64_t count() const { return count_; }
  [[nodiscard]] bool empty() const { return count_ == 0; }
  [[nodiscard]] Nanos min() const { return min_; }  // meaningful when not empty
  [[nodiscard]] Nanos max() const { return max_; }
  [[nodiscard]] double mean() const;
  // Nearest-rank quantile, p in [0, 1]; 0 when empty.
  [[nodiscard]] Nanos quantile(double p) const;

  // Calls fn(lower, upper, count) for each non-empty bucket in ascending order, with the
  // bucket's bounds clamped to [min, max].
  template <typename Fn>
  void for_each_bucket(Fn&& fn) const {
    for (std::size_t i = 0; i < counts_.size(); ++i) {
      if (counts_[i] == 0) continue;
      Nanos lo = bucket_lower(i);
      Nanos hi = bucket_upper(i);
      if (lo < min_) lo = min_;
      if (hi > max_) hi = max_;
      fn(lo, hi, counts_[i]);
    }
  }

 private:
  static std::size_t bucket_of(Nanos value);
  static Nanos bucket_lower(std::size_t i);
  static Nanos bucket_upper(std::size_t i);
  Nanos representative(std::size_t i) const;

  std::vector<std::uint64_t> counts_;  // allocated on the first add, kBuckets long
  std::uint64_t count_ = 0;
  Nanos min_ = 0;
  Nanos max_ = 0;
  double sum_ = 0.0;
};

}  // namespace rtu
