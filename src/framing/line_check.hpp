#pragma once
// Checks the line settings a capture is decoded with against the byte timing in it.
//
// On a serial line, characters sent back to back start exactly one character time apart, and
// most bytes of Modbus RTU traffic are sent so (inside frames). With a timestamp per byte, the
// spacing most bytes share is therefore the line's character time. A spacing shorter than one
// character at the chosen settings cannot happen on the wire: the line is faster than assumed
// (a 19200-baud capture decoded at 9600 splits almost every frame at "t3.5" and reads latencies
// as 0). A shared spacing of one and a half characters or more, at a rate that is itself a
// standard baud rate, means the line is most likely slower than assumed. Either way the warning
// names the rate the spacing implies.
//
// Batched reads (a USB adapter delivers many bytes per read) hide the spacing: then nothing is
// checked and nothing is said. Neither are timestamps too coarse to measure a character.
//
// Memory is fixed: spacings go into a logarithmic histogram fine enough (about 1.5% a bucket)
// to tell standard baud rates apart, so the first pass over a huge capture stays cheap.
#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "core/chunk.hpp"
#include "serial/line_settings.hpp"

namespace rtu {

class BucketIndex;

// The line a capture's byte timing points to: a standard rate at one character size.
struct InferredLine {
  std::uint32_t baud = 0;
  std::uint32_t bits_per_char = 0;  // 10 (8N1), 11 (8E1, 8O1, 8N2) or 12 (8E2, 8O2)
  Nanos spacing = 0;                // measured spacing of back-to-back bytes
  std::uint64_t agreeing = 0;       // spacings within the cluster around it
  std::uint64_t spacings = 0;       // spacings measured in all
};

class LineCheck {
 public:
  void add(const Chunk& chunk);
  // add() of each read, in one loop.
  void add(const ByteReads& reads);

  // Spacing of back-to-back bytes as measured (the mean of the densest cluster of spacings),
  // when the capture has per-byte timing, enough bytes, and a clear cluster; else nullopt.
  // `precision`: the step the timestamps are written with (0 = unknown).
  [[nodiscard]] std::optional<Nanos> byte_spacing(Nanos precision) const;

  // The standard rate and character size the measured spacing fits, when it can be measured
  // and fits one. `bits_per_char` fixes the character size (the user gave parity or stop
  // bits); else 11 bits (Modbus's 8E1) is tried first, then 10 and 12.
  [[nodiscard]] std::optional<InferredLine> infer_line(
      Nanos precision, std::optional<std::uint32_t> bits_per_char = std::nullopt) const;

  // A warning when the measured spacing contradicts `line`; nullopt when it agrees or cannot
  // be measured.
  [[nodiscard]] std::optional<std::string> warning(const LineSettings& line, Nanos precision) const;

 private:
  static constexpr std::size_t kPerOctave = 48;
  static constexpr std::size_t kBuckets = 1 + kPerOctave * 21;  // below 1 µs, then 1 µs to ~2 s
  static std::size_t bucket_by_formula(Nanos spacing);          // the definition
  static const BucketIndex& bucket_index();                     // the same, looked up
  struct Cluster {
    Nanos spacing = 0;
    std::uint64_t count = 0;
  };
  [[nodiscard]] std::optional<Cluster> densest_cluster(Nanos precision) const;
  // Single-byte reads (or bytes whose starts were measured) at `times`, in order.
  void add_single_bytes(const Nanos* times, std::size_t n);

  std::array<std::uint64_t, kBuckets> counts_{};
  std::array<std::uint64_t, kBuckets> sums_{};  // ns, for the exact mean of a cluster
  std::uint64_t spacings_ = 0;
  std::uint64_t chunks_ = 0;
  std::uint64_t multi_byte_chunks_ = 0;
  Nanos last_ = kUnknownTime;  // time of the previous single-byte chunk
  std::size_t bucket_ = 0;     // the bucket the last spacing went to: the next one's first guess
};

// The standard baud rate within 3% of `rate`, else nullopt.
std::optional<std::uint32_t> nearest_standard_baud(double rate);

}  // namespace rtu
