#pragma once
// Hexadecimal digits read back, for every reader of hex text (text captures, Saleae
// exports, device maps).
#include <array>
#include <cstdint>

namespace rtu {
namespace hex_digits_detail {

inline constexpr std::array<std::int8_t, 256> kValues = [] {
  std::array<std::int8_t, 256> t{};
  t.fill(-1);
  for (int c = '0'; c <= '9'; ++c)
    t[static_cast<std::size_t>(c)] = static_cast<std::int8_t>(c - '0');
  for (int c = 'a'; c <= 'f'; ++c) {
    t[static_cast<std::size_t>(c)] = static_cast<std::int8_t>(c - 'a' + 10);
    t[static_cast<std::size_t>(c - 'a' + 'A')] = static_cast<std::int8_t>(c - 'a' + 10);
  }
  return t;
}();

}  // namespace hex_digits_detail

// A hex digit's value (either case), -1 for any other character. A table, as the branches
// of a comparison chain are mispredicted on every other digit of real traffic.
inline int hex_digit_value(char c) {
  return hex_digits_detail::kValues[static_cast<unsigned char>(c)];
}

// The byte that the two hex digits at `p` spell, or a negative number when either of them is
// not a hex digit (a -1 in either place keeps the sign bit).
inline int hex_pair_value(const char* p) {
  return (hex_digit_value(p[0]) * 16) | hex_digit_value(p[1]);
}

}  // namespace rtu
