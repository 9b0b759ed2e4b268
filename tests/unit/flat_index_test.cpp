#include "core/flat_index.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <unordered_map>

namespace rtu {

namespace {

// Against std::unordered_map, through growth from empty to thousands of keys: every key
// put is found with its last value, and keys never put are not found. Keys are what a bus
// gives (neighbouring registers of a few slaves, which share their low or high bits) and
// now and then any 64-bit value, 0 included.
TEST(FlatIndex, FindsWhatAnUnorderedMapFinds) {
  FlatIndex<std::uint64_t> index;
  std::unordered_map<std::uint64_t, std::uint64_t> truth;
  std::mt19937_64 random(11);
  const auto a_key = [&random](int i) -> std::uint64_t {
    if (i % 97 == 0) return 0;
    if (i % 7 == 0) return random();
    return (random() % 8) << 48U | (random() % 600);
  };
  for (int i = 0; i < 50000; ++i) {
    const std::uint64_t key = a_key(i);
    const std::uint64_t value = random();
    index.put(key, value);
    truth[key] = value;
    // A key looked up at random: present or not, the index says what the map says.
    const std::uint64_t probe = a_key(i + 1);
    const std::uint64_t* found = index.find(probe);
    const auto expected = truth.find(probe);
    ASSERT_EQ(found != nullptr, expected != truth.end()) << "key " << probe;
    if (found != nullptr) {
      ASSERT_EQ(*found, expected->second) << "key " << probe;
    }
  }
  EXPECT_EQ(index.size(), truth.size());
  EXPECT_GT(truth.size(), 4000U);  // grown well past its first array
  for (const auto& [key, value] : truth) {
    const std::uint64_t* found = index.find(key);
    ASSERT_NE(found, nullptr) << "key " << key;
    EXPECT_EQ(*found, value) << "key " << key;
  }
}

TEST(FlatIndex, ClearForgetsEveryKeyAndTheIndexFillsAgain) {
  FlatIndex<int> index;
  for (std::uint64_t key = 0; key < 1000; ++key) index.put(key, static_cast<int>(key));
  index.clear();
  EXPECT_EQ(index.size(), 0U);
  for (std::uint64_t key = 0; key < 1000; ++key) EXPECT_EQ(index.find(key), nullptr) << key;
  index.put(500, 7);
  ASSERT_NE(index.find(500), nullptr);
  EXPECT_EQ(*index.find(500), 7);
  EXPECT_EQ(index.find(499), nullptr);
}

// Key 0 is a key like any other, not an empty slot.
TEST(FlatIndex, ZeroIsAKey) {
  FlatIndex<int> index;
  EXPECT_EQ(index.find(0), nullptr);
  index.put(0, 5);
  ASSERT_NE(index.find(0), nullptr);
  EXPECT_EQ(*index.find(0), 5);
  index.put(0, 6);
  EXPECT_EQ(*index.find(0), 6);
  EXPECT_EQ(index.size(), 1U);
}

}  // namespace
}  // namespace rtu
