#include "report/log_histogram.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "core/bucket_index.hpp"

namespace rtu {

namespace {

Nanos lower_bound_formula(std::size_t i) {
  return static_cast<Nanos>(std::ceil(static_cast<double>(LogHistogram::kFloor) *
                                      std::pow(LogHistogram::kGamma, static_cast<double>(i - 1))));
}

// Every bucket's lower bound, computed once (no logarithm or power per value), and found from
// them in a look-up and a comparison or two: a binary search over the 1,400 bounds took a
// tenth of a report's statistics time. Bound 0 (everything below kFloor) is never compared.
const BucketIndex& bucket_index() {
  static const BucketIndex index = [] {
    std::vector<std::int64_t> lower(LogHistogram::kBuckets, std::numeric_limits<Nanos>::min());
    for (std::size_t i = 1; i < lower.size(); ++i) lower[i] = lower_bound_formula(i);
    return BucketIndex(std::move(lower));
  }();
  return index;
}

}  // namespace

std::size_t LogHistogram::bucket_of(Nanos value) {
  if (value < kFloor) return 0;
  return bucket_index().find(value);
}

Nanos LogHistogram::bucket_lower(std::size_t i) {
  if (i < kBuckets) return bucket_index().lower(i);
  return lower_bound_formula(i);
}

Nanos LogHistogram::bucket_upper(std::size_t i) {
  if (i + 1 >= kBuckets) return std::numeric_limits<Nanos>::max();
  return bucket_lower(i + 1) - 1;
}

Nanos LogHistogram::representative(std::size_t i) const {
  Nanos r = 0;
  if (i == 0) {
    r = std::min<Nanos>(max_, kFloor - 1);
  } else {
    // The middle of the bucket in relative terms: at most (γ-1)/(γ+1) from either edge.
    const double lo = static_cast<double>(kFloor) * std::pow(kGamma, static_cast<double>(i - 1));
    r = static_cast<Nanos>(std::llround(lo * 2.0 * kGamma / (kGamma + 1.0)));
  }
  return std::clamp(r, min_, max_);
}

void LogHistogram::add(Nanos value) {
  if (counts_.empty()) counts_.assign(kBuckets, 0);
  if (count_ == 0) {
    min_ = value;
    max_ = value;
  } else {
    min_ = std::min(min_, value);
    max_ = std::max(max_, value);
  }
  ++counts_[bucket_of(value)];
  ++count_;
  sum_ += static_cast<double>(value);
}

void LogHistogram::merge(const LogHistogram& other) {
  if (other.count_ == 0) return;
  if (counts_.empty()) counts_.assign(kBuckets, 0);
  for (std::size_t i = 0; i < kBuckets; ++i) counts_[i] += other.counts_[i];
  if (count_ == 0) {
    min_ = other.min_;
    max_ = other.max_;
  } else {
    min_ = std::min(min_, other.min_);
    max_ = std::max(max_, other.max_);
  }
  count_ += other.count_;
  sum_ += other.sum_;
}

double LogHistogram::mean() const {
  return count_ == 0 ? 0.0 : sum_ / static_cast<double>(count_);
}

Nanos LogHistogram::quantile(double p) const {
  if (count_ == 0) return 0;
  if (p <= 0.0) return min_;
  if (p >= 1.0) return max_;
  auto rank = static_cast<std::uint64_t>(std::ceil(p * static_cast<double>(count_)));
  rank = std::clamp<std::uint64_t>(rank, 1, count_);
  if (rank == count_) return max_;
  if (rank == 1) return min_;
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < kBuckets; ++i) {
    seen += counts_[i];
    if (seen >= rank) return representative(i);
  }
  return max_;
}

}  // namespace rtu
