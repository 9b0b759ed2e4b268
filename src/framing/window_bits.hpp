#pragma once
// A bit for each position of the framer's byte window, where a read's new bytes clear a
// run of positions a word at a time: std::bitset clears them a bit per call, which cost a
// read of twenty bytes more than storing the bytes themselves.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

namespace rtu {

template <std::size_t kBits>
class WindowBits {
  static constexpr std::size_t kWordBits = 64;
  static_assert(kBits % kWordBits == 0, "whole words");

 public:
  [[nodiscard]] bool test(std::size_t i) const { return (words_[i / kWordBits] & bit(i)) != 0; }
  void set(std::size_t i) { words_[i / kWordBits] |= bit(i); }
  void clear(std::size_t i) { words_[i / kWordBits] &= ~bit(i); }
  // Clears `count` positions from `first` on (first < kBits), wrapping past the last
  // position to the first, as the window's slots do.
  void clear_run(std::size_t first, std::size_t count) {
    while (count > 0) {
      const std::size_t shift = first % kWordBits;
      const std::size_t n = std::min(count, kWordBits - shift);
      const std::uint64_t ones = n == kWordBits ? ~std::uint64_t{0} : (std::uint64_t{1} << n) - 1;
      words_[first / kWordBits] &= ~(ones << shift);
      count -= n;
      first = (first + n) % kBits;
    }
  }
  void clear_all() { words_.fill(0); }

 private:
  static std::uint64_t bit(std::size_t i) { return std::uint64_t{1} << (i % kWordBits); }

  std::array<std::uint64_t, kBits / kWordBits> words_{};
};

}  // namespace rtu
