#include "dissect/read_range_checks.hpp"

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

IssueSet ReadRangeChecks::of(const Space& space, std::uint32_t start, std::uint32_t quantity) {
  const auto space_bits = static_cast<std::uint32_t>(std::bit_cast<std::uintptr_t>(&space) >> 4U);
  const std::size_t slot = (start * 31U + quantity * 7U + space_bits) & (kEntries - 1);
  Entry& e = entries_[slot];
  if (e.space != &space || e.start != start || e.quantity != quantity) {
    e = Entry{&space, start, quantity, read_range_issues(space, start, quantity)};
  }
  return e.issues;
}

}  // namespace rtu::dissect
