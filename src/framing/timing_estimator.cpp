#include "framing/timing_estimator.hpp"

#include <algorithm>
#include <cmath>

#include "core/bucket_index.hpp"

namespace rtu {

std::size_t TimingEstimator::bucket_by_formula(Nanos interval) {
  const double micros = static_cast<double>(std::max<Nanos>(interval, 0)) / 1e3;
  const auto b = static_cast<std::size_t>(4.0 * std::log2(micros + 1.0));
  return std::min(b, kBuckets - 1);
}

std::size_t TimingEstimator::bucket_of(Nanos interval) {
  // The formula's buckets, without a logarithm per read.
  static const BucketIndex index(BucketIndex::lower_bounds_of(bucket_by_formula));
  return index.find(std::max<Nanos>(interval, 0));
}

Nanos TimingEstimator::bucket_upper(std::size_t bucket) {
  const double micros = std::exp2(static_cast<double>(bucket + 1) / 4.0) - 1.0;
  return static_cast<Nanos>(micros * 1e3);
}

void TimingEstimator::add(const Chunk& chunk) {
  ++chunks_;
  if (chunk.bytes.size() > 1) {
    ++multi_byte_chunks_;
    // Only reads that follow one another while traffic flows show the delivery period;
    // the quiet between bursts of polling says nothing about the adapter.
    const Nanos interval = last_t_ == kUnknownTime || chunk.time_clamped || chunk.read_late
                               ? kUnknownTime
                               : chunk.t_end - last_t_;
    if (interval != kUnknownTime && interval <= kMaxDeliveryPeriod) {
      ++multi_intervals_[bucket_of(interval)];
    }
  }
  // A late read's time says nothing of how long the next read came after it.
  last_t_ = chunk.read_late ? kUnknownTime : chunk.t_end;
}

bool TimingEstimator::mostly_single_bytes() const {
  // Up to 2% of batched reads still leave byte timing observable almost everywhere.
  return multi_byte_chunks_ * 50 <= chunks_;
}

Nanos TimingEstimator::resolution(Nanos precision) const {
  const Nanos floor = std::max<Nanos>(precision, kNanosPerMicro);
  if (mostly_single_bytes()) return floor;
  // Median interval between batched deliveries.
  std::uint64_t total = 0;
  for (const auto n : multi_intervals_) total += n;
  if (total == 0) return floor;
  std::uint64_t seen = 0;
  for (std::size_t b = 0; b < kBuckets; ++b) {
    seen += multi_intervals_[b];
    if (seen * 2 >= total) return std::max(floor, bucket_upper(b));
  }
  return floor;
}

}  // namespace rtu
