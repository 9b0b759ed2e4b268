#include "dissect/read_range_checks.hpp"

#include "dissect/range_slot.hpp"

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
    : slot_bits_(clamp_slot_bits(slot_bits)), entries_(std::size_t{1} << slot_bits_) {}

IssueSet ReadRangeChecks::of(const Space& space, std::uint32_t start, std::uint32_t quantity) {
  Entry& e = entries_[range_slot(space, start, quantity, slot_bits_)];
  if (e.space != &space || e.start != start || e.quantity != quantity) {
    e = Entry{&space, start, quantity, read_range_issues(space, start, quantity)};
  }
  return e.issues;
}

}  // namespace rtu::dissect
