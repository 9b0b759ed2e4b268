#include "core/short_copy.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstddef>

namespace rtu {
namespace {

// Every length up to well past the fixed-size moves, from every alignment: exactly the
// first n bytes are copied, and not one byte after them is written.
TEST(ShortCopy, CopiesExactlyTheBytesAskedForWhateverTheLength) {
  std::array<char, 96> source{};
  for (std::size_t i = 0; i < source.size(); ++i) source[i] = static_cast<char>('a' + i % 26);
  for (std::size_t offset = 0; offset < 8; ++offset) {
    for (std::size_t n = 0; n <= 80; ++n) {
      std::array<char, 96> target{};
      target.fill('#');
      copy_short(target.data() + offset, source.data() + offset, n);
      for (std::size_t i = 0; i < target.size(); ++i) {
        const bool copied = i >= offset && i < offset + n;
        ASSERT_EQ(target[i], copied ? source[i] : '#')
            << "n " << n << " offset " << offset << " byte " << i;
      }
    }
  }
}

}  // namespace
}  // namespace rtu
