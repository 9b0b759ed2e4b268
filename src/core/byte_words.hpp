#pragma once
// Eight bytes as one 64-bit word, for the loops that look at text eight characters at a
// time (timestamps of text captures, strings a JSON writer may have to escape).
#include <bit>
#include <cstdint>
#include <cstring>

namespace rtu::byte_words {

inline constexpr std::uint64_t kOnes = 0x0101010101010101ULL;  // 1 in every byte
inline constexpr std::uint64_t kHighBits = 0x80 * kOnes;       // the top bit of every byte

// The eight bytes at `p`, the first in the lowest byte whatever the machine's byte order.
inline std::uint64_t load(const char* p) {
  std::uint64_t word = 0;
  std::memcpy(&word, p, sizeof word);
  if constexpr (std::endian::native == std::endian::big) word = __builtin_bswap64(word);
  return word;
}

// Whether any byte of `word` is below `limit` (1-128). A borrow can flag only a byte above
// one that is below the limit, so the answer for the word is exact; a byte of 0x80 or more
// keeps its top bit out of the answer through its own complement.
constexpr bool has_byte_below(std::uint64_t word, std::uint8_t limit) {
  return ((word - limit * kOnes) & ~word & kHighBits) != 0;
}

}  // namespace rtu::byte_words
