// WindowBits against std::bitset: the same bits after any mix of sets, clears and runs
// cleared across the window's end.
#include "framing/window_bits.hpp"

#include <gtest/gtest.h>

#include <bitset>
#include <cstddef>
#include <random>

namespace rtu {
namespace {

constexpr std::size_t kBits = 256;

void expect_same(const WindowBits<kBits>& bits, const std::bitset<kBits>& oracle, int step) {
  for (std::size_t i = 0; i < kBits; ++i) {
    ASSERT_EQ(bits.test(i), oracle.test(i)) << "bit " << i << " after step " << step;
  }
}

TEST(WindowBits, ClearedRunsWrapPastTheEndLikeBitByBitClears) {
  WindowBits<kBits> bits;
  std::bitset<kBits> oracle;
  std::mt19937 random(7);
  for (int step = 0; step < 20000; ++step) {
    const std::size_t at = random() % kBits;
    switch (random() % 4) {
      case 0:
        bits.set(at);
        oracle.set(at);
        break;
      case 1:
        bits.clear(at);
        oracle.reset(at);
        break;
      case 2: {
        // Runs of every length up to the whole window, from every position.
        const std::size_t count = random() % (kBits + 1);
        bits.clear_run(at, count);
        for (std::size_t k = 0; k < count; ++k) oracle.reset((at + k) % kBits);
        break;
      }
      default:
        // Set many, so that clears have something to clear.
        for (std::size_t k = 0; k < 40; ++k) {
          const std::size_t i = random() % kBits;
          bits.set(i);
          oracle.set(i);
        }
    }
    expect_same(bits, oracle, step);
  }
  bits.clear_all();
  oracle.reset();
  expect_same(bits, oracle, -1);
}

TEST(WindowBits, AWholeWordRunClearsExactlyThatWord) {
  WindowBits<kBits> bits;
  for (std::size_t i = 0; i < kBits; ++i) bits.set(i);
  bits.clear_run(64, 64);
  for (std::size_t i = 0; i < kBits; ++i) EXPECT_EQ(bits.test(i), i < 64 || i >= 128) << i;
}

}  // namespace
}  // namespace rtu
