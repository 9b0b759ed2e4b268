#include "rng.hpp"

namespace rtu::sim {

// splitmix64 (Steele, Lea, Flood 2014): a 64-bit counter passed through a bijective mixer.
std::uint64_t Rng::next() {
  state_ += 0x9E3779B97F4A7C15ULL;
  std::uint64_t z = state_;
  z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31U);
}

// Rejection sampling keeps the draw exactly uniform (no modulo bias).
std::uint64_t Rng::below(std::uint64_t n) {
  const std::uint64_t limit = UINT64_MAX - (UINT64_MAX % n);
  std::uint64_t x = next();
  while (x >= limit) x = next();
  return x % n;
}

std::int64_t Rng::between(std::int64_t lo, std::int64_t hi) {
  const auto span = static_cast<std::uint64_t>(hi - lo) + 1U;
  return lo + static_cast<std::int64_t>(below(span));
}

double Rng::unit() {
  return static_cast<double>(next() >> 11U) * 0x1.0p-53;
}

Rng Rng::fork(std::uint64_t label) const {
  Rng mixer(state_ ^ (label * 0xD1B54A32D192ED03ULL));
  return Rng(mixer.next());
}

}  // namespace rtu::sim
