#pragma once
// Deterministic pseudo-random numbers for the simulator. The generator (splitmix64) and
// every derived draw are written out here rather than taken from <random>, whose
// distributions differ between standard libraries: the same seed must give byte-identical
// captures on every build.
#include <cstdint>

#include "core/time.hpp"

namespace rtu::sim {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}

  std::uint64_t next();
  // Uniform in [0, n); n > 0.
  std::uint64_t below(std::uint64_t n);
  // Uniform in [lo, hi], both included; lo <= hi.
  std::int64_t between(std::int64_t lo, std::int64_t hi);
  // Uniform in [0, 1).
  double unit();
  bool chance(double probability) { return unit() < probability; }
  std::uint8_t byte() { return static_cast<std::uint8_t>(next() >> 56U); }
  std::uint16_t word() { return static_cast<std::uint16_t>(next() >> 48U); }
  Nanos nanos(Nanos lo, Nanos hi) { return between(lo, hi); }

  // An independent stream derived from this generator's seed and a label, so adding draws
  // to one part of the simulation does not shift the numbers another part sees.
  [[nodiscard]] Rng fork(std::uint64_t label) const;

 private:
  std::uint64_t state_;
};

}  // namespace rtu::sim
