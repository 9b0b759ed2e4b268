#pragma once
// A fixed number of equal time buckets covering a capture of any length: when a time falls
// past the last bucket, neighbouring buckets are merged pairwise and the width doubles, so
// memory stays constant and the whole capture stays covered. Every series started with the
// same origin and first width can be aligned bucket for bucket (align_to) because widths
// only ever double.
//
// T is the per-bucket value: default-constructible with `void merge(const T&)`.
#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/time.hpp"

namespace rtu {

template <typename T>
class TimeBuckets {
 public:
  TimeBuckets(Nanos origin, Nanos first_width, std::size_t count)
      : origin_(origin), width_(first_width > 0 ? first_width : 1), buckets_(count) {}

  // The bucket that holds time `t` (times before the origin go to the first bucket),
  // widening first if `t` lies past the end.
  T& at(Nanos t) {
    // Times come nearly in order, so most fall in the bucket the last one did: answered
    // without the 64-bit division (a report asks this several times per frame and once per
    // decoded point).
    if (t >= last_start_ && t < last_end_) return buckets_[last_];
    while (t >= end()) widen();
    if (t < origin_) return buckets_.front();
    last_ = static_cast<std::size_t>((t - origin_) / width_);
    last_start_ = bucket_start(last_);
    last_end_ = last_start_ + width_;
    return buckets_[last_];
  }

  // Spreads `amount` over [from, to) in proportion to the overlap with each bucket; the
  // caller's `add(T&, double share)` receives each bucket's share.
  template <typename Add>
  void spread(Nanos from, Nanos to, Add&& add) {
    if (to <= from) {
      add(at(from), 1.0);
      return;
    }
    // Within the bucket at() found last (nearly every frame: buckets last seconds): all of
    // it there, as the loop below gives, without its division.
    if (from >= last_start_ && to <= last_end_) {
      add(buckets_[last_], 1.0);
      return;
    }
    if (from < origin_) from = origin_;
    if (to <= from) return;
    while (to > end()) widen();
    const double total = static_cast<double>(to - from);
    auto i = static_cast<std::size_t>((from - origin_) / width_);
    for (; i < buckets_.size(); ++i) {
      const Nanos lo = std::max(from, bucket_start(i));
      const Nanos hi = std::min(to, bucket_start(i) + width_);
      if (hi <= lo) break;
      add(buckets_[i], static_cast<double>(hi - lo) / total);
    }
  }

  // Widens until this series' width equals `other_width` (a power-of-two multiple).
  void align_to(Nanos other_width) {
    while (width_ < other_width) widen();
  }

  [[nodiscard]] Nanos origin() const { return origin_; }
  [[nodiscard]] Nanos width() const { return width_; }
  [[nodiscard]] Nanos end() const { return origin_ + width_ * static_cast<Nanos>(buckets_.size()); }
  [[nodiscard]] Nanos bucket_start(std::size_t i) const {
    return origin_ + width_ * static_cast<Nanos>(i);
  }
  [[nodiscard]] std::size_t size() const { return buckets_.size(); }
  [[nodiscard]] const T& operator[](std::size_t i) const { return buckets_[i]; }

 private:
  void widen() {
    const std::size_t n = buckets_.size();
    for (std::size_t i = 0; i < n; ++i) {
      T merged;
      if (2 * i < n) {
        merged = buckets_[2 * i];
        if (2 * i + 1 < n) merged.merge(buckets_[2 * i + 1]);
      }
      buckets_[i] = merged;
    }
    width_ *= 2;
    last_end_ = last_start_;  // the bucket of the last time moved: ask again
  }

  Nanos origin_;
  Nanos width_;
  std::vector<T> buckets_;
  // The bucket at() found last and the times it holds; empty ([0, 0)) until then.
  std::size_t last_ = 0;
  Nanos last_start_ = 0;
  Nanos last_end_ = 0;
};

}  // namespace rtu
