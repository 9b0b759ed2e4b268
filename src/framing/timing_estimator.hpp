#pragma once
// Estimates how fine a capture's timestamps really are, from the chunks themselves.
//
// A host serial read returns whatever the driver has buffered. With a USB adapter, bytes
// wait in the adapter until its latency timer (often 16 ms) or a full packet sends them,
// so a chunk's time can be that much later than its bytes, and any silence shorter than
// that delivery period is invisible. When most chunks hold several bytes, the typical
// interval between chunks that hold several bytes is that period. When chunks hold one
// byte each (per-byte sources, logic analysers), the timestamps' own precision is the limit.
//
// Memory is fixed (a logarithmic histogram), so the first pass over a huge capture is cheap.
#include <array>
#include <cstdint>

#include "core/chunk.hpp"

namespace rtu {

class TimingEstimator {
 public:
  void add(const Chunk& chunk);
  // `precision`: the step the timestamps are written with (0 = unknown).
  [[nodiscard]] Nanos resolution(Nanos precision) const;
  [[nodiscard]] bool mostly_single_bytes() const;
  [[nodiscard]] std::uint64_t chunks() const { return chunks_; }

 private:
  static constexpr std::size_t kBuckets = 160;  // 4 per octave from 1 µs: up to ~10^12 µs
  static std::size_t bucket_of(Nanos interval);
  static Nanos bucket_upper(std::size_t bucket);

  std::array<std::uint64_t, kBuckets> multi_intervals_{};
  std::uint64_t chunks_ = 0;
  std::uint64_t multi_byte_chunks_ = 0;
  Nanos last_t_ = kUnknownTime;
};

}  // namespace rtu
