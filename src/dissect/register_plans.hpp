#pragma once
// How a run of register bytes splits into a device map's points: which point each value
// belongs to, where its bytes lie and whether it is whole, partial, a spare register or an
// address the map does not define. That depends only on the space, the start address and
// the number of bytes, and a master polls the same few ranges over and over, so each split
// is worked out once and remembered (a small table per decoder, as ReadRangeChecks does):
// the register decoder then only reads the values out of the bytes.
#include <cstdint>
#include <span>
#include <vector>

#include "dissect/device_map.hpp"

namespace rtu::dissect {

// One value of a run of register bytes: the bytes [offset, offset + length) of the run.
struct RegisterStep {
  enum class Kind : std::uint8_t {
    kValue,      // the whole of `point`'s value
    kPartial,    // part of `point`'s value: the transfer starts or ends inside it
    kSpare,      // a spare register travelling with `point` (spare_index > 0)
    kUndefined,  // an address the map does not define (`point` is null)
  };
  const Point* point = nullptr;
  std::uint32_t addr = 0;  // in the space's addressing
  std::uint16_t offset = 0;
  std::uint8_t length = 0;  // 1 to 8 bytes
  std::uint8_t spare_index = 0;
  Kind kind = Kind::kUndefined;
};

// The split of `bytes` register bytes starting at `start` in `space`, unremembered.
void plan_registers(const Space& space, std::uint32_t start, std::size_t bytes,
                    std::vector<RegisterStep>& out);

class RegisterPlans {
 public:
  // A table of 2^slot_bits pairs of splits (1 to 16 bits). A range may be kept in either of
  // its slot's pair, the one asked for longer ago giving way: with one split a slot, two of
  // the ranges a bus polls over and over that shared a slot were worked out again each time
  // they alternated, and on the simulator's bus 38% of the asks missed.
  explicit RegisterPlans(unsigned slot_bits = kDefaultSlotBits);

  // plan_registers(), remembered by the space's address, the start and the length. A Space
  // must outlive the plans that saw it: a later one at the same address would get its splits.
  std::span<const RegisterStep> of(const Space& space, std::uint32_t start, std::size_t bytes);

 private:
  struct Entry {
    const Space* space = nullptr;
    std::uint32_t start = 0;
    std::size_t bytes = 0;
    std::vector<RegisterStep> steps;
  };
  static constexpr unsigned kDefaultSlotBits = 7;

  unsigned slot_bits_;
  std::vector<Entry> entries_;            // the pair of slot i at 2i and 2i + 1
  std::vector<std::uint8_t> asked_last_;  // per slot: which of its pair was asked for last
};

}  // namespace rtu::dissect
