#pragma once
// An index from 64-bit keys to small values (iterators, string views) in one array, with
// open addressing and linear probing. The tables a bus fills (its registers' names, its
// kinds of request, its point series) are looked up at every value and every request and
// hold at most a few thousand keys that recur polling cycle after polling cycle. Here a
// key's home slot is one multiply and a shift away, and it is nearly always found there;
// std::unordered_map divides the hash by its bucket count and then follows a node pointer.
//
// Values are copied when the array grows, so they must not point into the index: they
// refer to what the caller keeps elsewhere (map entries, strings that do not move).
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rtu {

template <typename Value>
class FlatIndex {
 public:
  FlatIndex() { resize(kFirstCapacity); }

  // The value of `key`, or nullptr. Valid until the next put() or clear().
  [[nodiscard]] const Value* find(std::uint64_t key) const {
    // At most half the slots are used, so the probe meets an empty one.
    for (std::size_t i = home(key);; i = (i + 1) & mask_) {
      const Slot& slot = slots_[i];
      if (!slot.used) return nullptr;
      if (slot.key == key) return &slot.value;
    }
  }

  // Adds `key` with `value`, or gives a key already there `value`.
  void put(std::uint64_t key, const Value& value) {
    if ((size_ + 1) * 2 > slots_.size()) grow();
    for (std::size_t i = home(key);; i = (i + 1) & mask_) {
      Slot& slot = slots_[i];
      if (!slot.used) {
        slot = Slot{key, value, true};
        ++size_;
        return;
      }
      if (slot.key == key) {
        slot.value = value;
        return;
      }
    }
  }

  [[nodiscard]] std::size_t size() const { return size_; }

  // Forgets every key; the array keeps its size.
  void clear() {
    for (Slot& slot : slots_) slot.used = false;
    size_ = 0;
  }

 private:
  struct Slot {
    std::uint64_t key = 0;  // any value, 0 included: `used` tells an empty slot
    Value value{};
    bool used = false;
  };
  static constexpr std::size_t kFirstCapacity = 64;

  // Fibonacci hashing: keys that differ in a few low bits (neighbouring registers) or only
  // in high ones (the slave) spread over the slots alike.
  [[nodiscard]] std::size_t home(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> shift_);
  }

  // `capacity` empty slots, a power of two.
  void resize(std::size_t capacity) {
    slots_.assign(capacity, Slot{});
    mask_ = capacity - 1;
    shift_ = 64U - static_cast<unsigned>(std::countr_zero(capacity));
    size_ = 0;
  }

  void grow() {
    const std::vector<Slot> old = std::move(slots_);
    resize(2 * old.size());
    for (const Slot& slot : old) {
      if (slot.used) put(slot.key, slot.value);
    }
  }

  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  unsigned shift_ = 0;  // 64 minus log2 of the slot count
  std::size_t size_ = 0;
};

}  // namespace rtu
