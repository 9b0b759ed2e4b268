#pragma once
// Copies of a few bytes whose length is known only at run time. memcpy of a variable length
// is a call into the C library, which costs more than the copy itself for the keys, values
// and timestamps that every record and every line of a text capture moves; a few moves of
// fixed size (overlapping where the length falls between them) are a handful of instructions.
#include <cstddef>
#include <cstring>

namespace rtu {

// Copies `n` bytes, at most 32, from `from` to `to` (which must not overlap) by fixed-size
// moves, overlapping where `n` falls between them.
inline void copy_at_most_32(char* to, const char* from, std::size_t n) {
  if (n >= 16) {
    std::memcpy(to, from, 16);
    std::memcpy(to + n - 16, from + n - 16, 16);
  } else if (n >= 8) {
    std::memcpy(to, from, 8);
    std::memcpy(to + n - 8, from + n - 8, 8);
  } else if (n >= 4) {
    std::memcpy(to, from, 4);
    std::memcpy(to + n - 4, from + n - 4, 4);
  } else {
    for (std::size_t k = 0; k < n; ++k) to[k] = from[k];
  }
}

// Copies `n` bytes from `from` to `to` (which must not overlap): up to 32 by fixed-size
// moves, longer ones by memcpy.
inline void copy_short(char* to, const char* from, std::size_t n) {
  if (n > 32) {
    std::memcpy(to, from, n);
  } else {
    copy_at_most_32(to, from, n);
  }
}

}  // namespace rtu
