#include "dissect/register_plans.hpp"

#include <algorithm>

#include "dissect/range_slot.hpp"

namespace rtu::dissect {

void plan_registers(const Space& space, std::uint32_t start, std::size_t bytes,
                    std::vector<RegisterStep>& out) {
  out.clear();
  const bool bytewise = space.addressing == Addressing::kByte;
  std::size_t off = 0;
  while (off < bytes) {
    const std::uint32_t addr = bytewise ? start + static_cast<std::uint32_t>(off)
                                        : start + static_cast<std::uint32_t>(off / 2);
    const std::size_t left = bytes - off;
    const Point* p = space.point_at(addr);
    RegisterStep& s = out.emplace_back();
    s.addr = addr;
    s.offset = static_cast<std::uint16_t>(off);
    if (p == nullptr) {
      // An undefined register: one word, or in a byte space the bytes up to the next point
      // or register boundary.
      std::size_t len = 2;
      if (bytewise && ((addr % 2) != 0 || space.point_at(addr + 1) != nullptr)) len = 1;
      len = std::min(len, left);
      s.kind = RegisterStep::Kind::kUndefined;
      s.length = static_cast<std::uint8_t>(len);
      off += len;
      continue;
    }
    s.point = p;
    const std::uint32_t rel_units = addr - p->addr;
    const std::size_t rel_bytes = bytewise ? rel_units : std::size_t{rel_units} * 2;
    const std::size_t value_bytes = p->value_bytes();
    if (rel_bytes < value_bytes) {
      const std::size_t want = value_bytes - rel_bytes;
      const std::size_t len = std::min(want, left);
      // A transfer that starts or ends inside the point shows its bytes, not a value.
      s.kind = rel_bytes == 0 && left >= want ? RegisterStep::Kind::kValue
                                              : RegisterStep::Kind::kPartial;
      s.length = static_cast<std::uint8_t>(len);
      off += len;
      continue;
    }
    // A spare register travelling with the point.
    const std::size_t spare_byte = rel_bytes - value_bytes;
    const std::size_t len = std::min<std::size_t>(2 - (spare_byte % 2), left);
    s.kind = RegisterStep::Kind::kSpare;
    s.spare_index = static_cast<std::uint8_t>(spare_byte / 2 + 1);
    s.length = static_cast<std::uint8_t>(len);
    off += len;
  }
}

RegisterPlans::RegisterPlans(unsigned slot_bits)
    : slot_bits_(clamp_slot_bits(slot_bits)),
      entries_(std::size_t{2} << slot_bits_),
      asked_last_(std::size_t{1} << slot_bits_, 0) {}

std::span<const RegisterStep> RegisterPlans::of(const Space& space, std::uint32_t start,
                                                std::size_t bytes) {
  const std::size_t slot = range_slot(space, start, bytes, slot_bits_);
  for (std::uint8_t way = 0; way < 2; ++way) {
    Entry& e = entries_[2 * slot + way];
    if (e.space == &space && e.start == start && e.bytes == bytes) {
      asked_last_[slot] = way;
      return e.steps;
    }
  }
  const auto way = static_cast<std::uint8_t>(1 - asked_last_[slot]);
  Entry& e = entries_[2 * slot + way];
  asked_last_[slot] = way;
  e.space = &space;
  e.start = start;
  e.bytes = bytes;
  plan_registers(space, start, bytes, e.steps);
  return e.steps;
}

}  // namespace rtu::dissect
