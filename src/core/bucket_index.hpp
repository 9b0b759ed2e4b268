#pragma once
// Which of a row of consecutive ranges holds a value, in a table look-up and a comparison or
// two, for the logarithmic histograms that count every read, spacing or latency of a capture.
//
// A bucket is given by its least value (lower[b], ascending; bucket 0 holds everything below
// lower[1]). A value's leading bit and the kSliceBits bits after it name a slice of the value
// range less than 1% wide in relative terms; the table holds the bucket of each slice's least
// value, and the comparisons move on to the bucket whose range holds the value. The answer is
// exact whatever the buckets' widths: narrower buckets only take more comparisons.
//
// Histograms defined by a formula (a logarithm of the value) get their bounds from
// lower_bounds_of(): the formula is evaluated a few thousand times once, and never again per
// value, so the buckets are exactly the formula's.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace rtu {

class BucketIndex {
 public:
  static constexpr unsigned kSliceBits = 7;

  explicit BucketIndex(std::vector<std::int64_t> lower);

  // The bucket of `value` (≥ 0).
  [[nodiscard]] std::size_t find(std::int64_t value) const {
    std::size_t bucket = slice_start_[slice_of(static_cast<std::uint64_t>(value))];
    while (bucket + 1 < lower_.size() && lower_[bucket + 1] <= value) ++bucket;
    return bucket;
  }
  [[nodiscard]] std::int64_t lower(std::size_t bucket) const { return lower_[bucket]; }
  [[nodiscard]] std::size_t buckets() const { return lower_.size(); }

  // The least value of each bucket `formula` (which never decreases as the value grows) gives
  // on 0 … 2^62: bucket b's is the least value the formula puts in b or above.
  static std::vector<std::int64_t> lower_bounds_of(
      const std::function<std::size_t(std::int64_t)>& formula);

 private:
  static std::size_t slice_of(std::uint64_t value);
  std::vector<std::int64_t> lower_;
  std::vector<std::uint16_t> slice_start_;
};

}  // namespace rtu
