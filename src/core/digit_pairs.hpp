#pragma once
// Tables of two-character digit pairs: a number's two digits in one copy, instead of a
// division or a lookup per digit. The time formatter writes fractions of a second with the
// decimal ones; the JSON writer writes every frame's bytes with the hexadecimal ones.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace rtu {
namespace digit_pairs_detail {

// Pairs of the `base` digits of `digits`: "00" "01" ... up to base*base-1.
template <std::size_t kBase>
constexpr std::array<char, 2 * kBase * kBase> make_pairs(std::string_view digits) {
  std::array<char, 2 * kBase * kBase> pairs{};
  for (std::size_t n = 0; n < kBase * kBase; ++n) {
    pairs[2 * n] = digits[n / kBase];
    pairs[2 * n + 1] = digits[n % kBase];
  }
  return pairs;
}

inline constexpr auto kDecimalPairs = make_pairs<10>("0123456789");
inline constexpr auto kHexPairs = make_pairs<16>("0123456789abcdef");

}  // namespace digit_pairs_detail

// The two decimal digits of `n` (below 100), not terminated.
inline const char* decimal_pair(std::uint64_t n) {
  return &digit_pairs_detail::kDecimalPairs[2 * n];
}

// The two lowercase hexadecimal digits of `byte`, not terminated.
inline const char* hex_pair(std::uint8_t byte) {
  return &digit_pairs_detail::kHexPairs[2 * std::size_t{byte}];
}

}  // namespace rtu
