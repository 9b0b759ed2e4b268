#pragma once
// The slot of a small remembering table (ReadRangeChecks, RegisterPlans) that a range of a
// space falls in: the decoders ask these tables once a frame, for the few ranges a master
// polls over and over.
#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>

#include "dissect/device_map.hpp"

namespace rtu::dissect {

// A table's size in bits of slot number, kept to 1 to 16.
constexpr unsigned clamp_slot_bits(unsigned slot_bits) {
  return std::clamp(slot_bits, 1U, 16U);
}

// Multiplied by an odd constant and its top bits taken, so that every bit of the space's
// address and of the range moves the slot.
inline std::size_t range_slot(const Space& space, std::uint32_t start, std::uint64_t length,
                              unsigned slot_bits) {
  const std::uint64_t key =
      std::bit_cast<std::uintptr_t>(&space) ^ (std::uint64_t{start} << 32U) ^ (length << 16U);
  return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> (64U - slot_bits));
}

}  // namespace rtu::dissect
