#pragma once
// A small direct-mapped cache of 64-bit keys in front of a std::unordered_map. Finding a
// key in an unordered_map divides its hash by the bucket count (tens of cycles) and then
// follows a node pointer; the tables a bus fills (its registers, its kinds of request) are
// looked up at every value and every request, yet hold a few hundred keys that recur
// polling cycle after polling cycle. Here a key's slot is one multiply and a shift away.
// A miss says nothing: the caller asks its table and put()s the answer.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>

namespace rtu {

template <typename Value, std::size_t kSlots>
class KeyCache {
  static_assert(kSlots >= 2 && std::has_single_bit(kSlots),
                "a power of two: the slot is the hash's top bits");

 public:
  // The value cached for `key`, or nullptr.
  [[nodiscard]] const Value* find(std::uint64_t key) const {
    const Slot& slot = slots_[slot_of(key)];
    return slot.used && slot.key == key ? &slot.value : nullptr;
  }

  // Caches `value` for `key`, in place of whatever key shared its slot.
  void put(std::uint64_t key, const Value& value) { slots_[slot_of(key)] = Slot{key, value, true}; }

  // Forgets every key (when what the values point to goes away).
  void clear() {
    for (Slot& slot : slots_) slot.used = false;
  }

 private:
  struct Slot {
    std::uint64_t key = 0;
    Value value{};
    bool used = false;
  };

  // Fibonacci hashing: keys that differ in a few low bits (neighbouring registers) or only
  // in high ones (the slave) spread over the slots alike.
  static std::size_t slot_of(std::uint64_t key) {
    constexpr int kShift = 64 - std::countr_zero(kSlots);
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> kShift);
  }

  std::array<Slot, kSlots> slots_{};
};

}  // namespace rtu
