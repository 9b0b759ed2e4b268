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
// Intervals longer than kMaxDeliveryPeriod are pauses in the traffic, not deliveries, and
// are left out. The framer raises the estimate later where a CRC-valid frame shows that a
// read came later than this (Framer::learn_from).
//
// Memory is fixed (a logarithmic histogram), so the first pass over a huge capture is cheap.
#include <array>
#include <cstdint>

#include "core/chunk.hpp"

namespace rtu {

// No USB serial adapter in use holds bytes longer than this: FTDI's latency timer is
// 16 ms by default (up to 255 ms if someone raised it), CH340/CP210x/PL2303 deliver
// within a few ms.
inline constexpr Nanos kMaxDeliveryPeriod = 64 * kNanosPerMilli;

class TimingEstimator {
 public:
  void add(const Chunk& chunk);
  // add() of each read: single bytes, which only count.
  void add(const ByteReads& reads) {
    if (reads.size() == 0) return;
    chunks_ += reads.size();
    last_t_ = reads.t_ends[reads.size() - 1];
  }
  // `precision`: the step the timestamps are written with (0 = unknown).
  [[nodiscard]] Nanos resolution(Nanos precision) const;
  [[nodiscard]] bool mostly_single_bytes() const;
  [[nodiscard]] std::uint64_t chunks() const { return chunks_; }

 private:
  static constexpr std::size_t kBuckets = 160;  // 4 per octave from 1 µs: up to ~10^12 µs
  static std::size_t bucket_by_formula(Nanos interval);  // the definition
  static std::size_t bucket_of(Nanos interval);          // the same, looked up
  static Nanos bucket_upper(std::size_t bucket);

  std::array<std::uint64_t, kBuckets> multi_intervals_{};
  std::uint64_t chunks_ = 0;
  std::uint64_t multi_byte_chunks_ = 0;
  Nanos last_t_ = kUnknownTime;
};

}  // namespace rtu
