#include "core/bucket_index.hpp"

#include <algorithm>
#include <bit>
#include <limits>
#include <stdexcept>

namespace rtu {
namespace {

constexpr std::uint64_t kExact = std::uint64_t{1} << BucketIndex::kSliceBits;
constexpr unsigned kValueBits = 63;  // values are int64 ≥ 0
constexpr std::int64_t kTop = std::int64_t{1} << 62;

}  // namespace

// Values below 2^kSliceBits are their own slice; above, the leading bit and the kSliceBits
// bits after it.
std::size_t BucketIndex::slice_of(std::uint64_t value) {
  if (value < kExact) return static_cast<std::size_t>(value);
  const auto lead = static_cast<unsigned>(63 - std::countl_zero(value));
  const std::uint64_t below = (value >> (lead - kSliceBits)) & (kExact - 1);
  return static_cast<std::size_t>(kExact + ((lead - kSliceBits) << kSliceBits) + below);
}

BucketIndex::BucketIndex(std::vector<std::int64_t> lower) : lower_(std::move(lower)) {
  if (lower_.empty() || lower_.size() > std::numeric_limits<std::uint16_t>::max()) {
    throw std::invalid_argument("BucketIndex: 1 to 65535 buckets");
  }
  lower_[0] = std::numeric_limits<std::int64_t>::min();
  slice_start_.assign(kExact + ((kValueBits - kSliceBits) << kSliceBits), 0);
  for (std::size_t slice = 0; slice < slice_start_.size(); ++slice) {
    // The slice's least value.
    std::uint64_t least = slice;
    if (slice >= kExact) {
      const std::size_t lead = kSliceBits + ((slice - kExact) >> kSliceBits);
      least = (std::uint64_t{1} << lead) | ((slice & (kExact - 1)) << (lead - kSliceBits));
    }
    const auto above =
        std::upper_bound(lower_.begin() + 1, lower_.end(), static_cast<std::int64_t>(least));
    slice_start_[slice] = static_cast<std::uint16_t>(above - lower_.begin() - 1);
  }
}

std::vector<std::int64_t> BucketIndex::lower_bounds_of(
    const std::function<std::size_t(std::int64_t)>& formula) {
  std::vector<std::int64_t> lower{std::numeric_limits<std::int64_t>::min()};
  const std::size_t last = formula(kTop);
  std::int64_t from = 0;
  for (std::size_t bucket = 1; bucket <= last; ++bucket) {
    // The least value in [from, kTop] the formula puts in `bucket` or above: bracketed by
    // steps that double (the next bound is near on a logarithmic scale), then halved.
    std::int64_t lo = from;
    std::int64_t hi = from;
    std::int64_t step = 1;
    while (formula(hi) < bucket) {
      lo = hi + 1;
      hi = step > kTop - from ? kTop : from + step;
      step = step >= kTop / 2 ? kTop : step * 2;
    }
    while (lo < hi) {
      const std::int64_t mid = lo + (hi - lo) / 2;
      if (formula(mid) >= bucket) {
        hi = mid;
      } else {
        lo = mid + 1;
      }
    }
    lower.push_back(lo);
    from = lo;
  }
  return lower;
}

}  // namespace rtu
