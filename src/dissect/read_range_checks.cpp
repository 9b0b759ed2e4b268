#include "dissect/read_range_checks.hpp"

#include <algorithm>
#include <bit>

namespace rtu::dissect {

IssueSet read_range_issues(const Space& space, std::uint32_t start, std::uint32_t quantity) {
  IssueSet issues;
  const bool bytewise = space.addressing == Addressing::kByte;
  const std::uint32_t units = bytewise ? quantity * 2 : quantity;
  const std::uint32_t end = start + units;
  std::uint32_t a = start;
  while (a < end) {
    const Point* p = space.point_at(a);
    if (p == nullptr) {
      issues.add(IssueId::kUndefinedRegister);
      const Point* next = space.point_from(a);
      if (next == nullptr) break;
      a = next->addr;
      continue;
    }
    const std::uint32_t value_end = p->addr + p->value_units(space.addressing);
    if ((a > p->addr && a < value_end) || (end > p->addr && end < value_end)) {
      issues.add(IssueId::kPartialPoint);
    }
    a = p->addr + p->units(space.addressing);
  }
  return issues;
}

ReadRangeChecks::ReadRangeChecks(unsigned slot_bits)
    : slot_bits_(std::clamp(slot_bits, 1U, 16U)), entries_(std::size_t{1} << slot_bits_) {}

IssueSet ReadRangeChecks::of(const Space& space, std::uint32_t start, std::uint32_t quantity) {
  // Multiplied by an odd constant and its top bits taken, so that every bit of the space's
  // address and of the range moves the slot.
  const std::uint64_t key = std::bit_cast<std::uintptr_t>(&space) ^ (std::uint64_t{start} << 32U) ^
                            (std::uint64_t{quantity} << 16U);
  const auto slot = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> (64U - slot_bits_));
  Entry& e = entries_[slot];
  if (e.space != &space || e.start != start || e.quantity != quantity) {
    e = Entry{&space, start, quantity, read_range_issues(space, start, quantity)};
  }
  return e.issues;
}

}  // namespace rtu::dissect
