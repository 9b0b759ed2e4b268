#include "core/key_cache.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <unordered_map>

namespace rtu {
namespace {

// Whatever keys come and go, the cache never answers with another key's value: a hit is
// the value last put for that very key, and a key whose slot another key took is a miss.
TEST(KeyCache, AHitIsAlwaysTheValueLastPutForThatKey) {
  KeyCache<std::uint64_t, 64> cache;
  std::unordered_map<std::uint64_t, std::uint64_t> truth;
  std::mt19937_64 random(7);
  std::uint64_t hits = 0;
  std::uint64_t misses = 0;
  for (int i = 0; i < 200000; ++i) {
    // Neighbouring registers of a few slaves, as a bus polls them, and now and then any key.
    const std::uint64_t key = i % 7 == 0 ? random() : (random() % 4) << 48U | (random() % 12);
    if (const std::uint64_t* cached = cache.find(key)) {
      ASSERT_EQ(truth.count(key), 1U) << "key " << key;
      ASSERT_EQ(*cached, truth[key]) << "key " << key;
      ++hits;
    } else {
      ++misses;
    }
    const std::uint64_t value = random();
    truth[key] = value;
    cache.put(key, value);
  }
  // Both ways taken: the test would pass vacuously with a cache that never hits.
  EXPECT_GT(hits, 10000U);
  EXPECT_GT(misses, 10000U);
}

TEST(KeyCache, ClearForgetsEveryKey) {
  KeyCache<int, 16> cache;
  for (std::uint64_t key = 0; key < 100; ++key) cache.put(key, static_cast<int>(key));
  std::size_t found = 0;
  for (std::uint64_t key = 0; key < 100; ++key) found += cache.find(key) != nullptr ? 1U : 0U;
  EXPECT_GT(found, 0U);
  EXPECT_LE(found, 16U);
  cache.clear();
  for (std::uint64_t key = 0; key < 100; ++key) EXPECT_EQ(cache.find(key), nullptr) << key;
}

// Key 0 is a key like any other, not an empty slot.
TEST(KeyCache, ZeroIsAKey) {
  KeyCache<int, 8> cache;
  EXPECT_EQ(cache.find(0), nullptr);
  cache.put(0, 5);
  ASSERT_NE(cache.find(0), nullptr);
  EXPECT_EQ(*cache.find(0), 5);
}

}  // namespace
}  // namespace rtu
