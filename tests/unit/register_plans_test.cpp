// The split of a run of register bytes into a map's points is remembered per decoder: the
// remembered split is always the unremembered one, for every bundled map's spaces and ranges
// asked in any order, in tables of any size; and a split covers its bytes exactly once, in
// order, with each kind of step where the maps have one.
#include "dissect/register_plans.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "dissect_test_support.hpp"

namespace rtu::dissect {
namespace {

using testing::asked_again_order;
using testing::ranges_around_bundled_points;
using testing::SpaceRange;

bool same_steps(const std::vector<RegisterStep>& a, std::span<const RegisterStep> b) {
  return std::equal(
      a.begin(), a.end(), b.begin(), b.end(), [](const RegisterStep& x, const RegisterStep& y) {
        return x.point == y.point && x.addr == y.addr && x.offset == y.offset &&
               x.length == y.length && x.spare_index == y.spare_index && x.kind == y.kind;
      });
}

TEST(RegisterPlans, ASplitCoversItsBytesOnceInOrderWithEveryKindOfStep) {
  std::size_t kinds[4] = {};
  std::vector<RegisterStep> steps;
  // Each range's length in bytes: odd ones too (a byte count a device got wrong).
  for (const SpaceRange& r : ranges_around_bundled_points()) {
    plan_registers(*r.space, r.start, r.length, steps);
    const bool bytewise = r.space->addressing == Addressing::kByte;
    std::size_t next = 0;
    for (const RegisterStep& s : steps) {
      ASSERT_EQ(s.offset, next) << "space " << r.space->id << " from " << r.start;
      ASSERT_GT(s.length, 0U);
      EXPECT_EQ(s.addr, r.start + (bytewise ? s.offset : s.offset / 2U));
      EXPECT_EQ(s.point == nullptr, s.kind == RegisterStep::Kind::kUndefined);
      EXPECT_EQ(s.spare_index > 0, s.kind == RegisterStep::Kind::kSpare);
      if (s.kind == RegisterStep::Kind::kValue) {
        EXPECT_EQ(s.point->addr, s.addr);
        EXPECT_EQ(s.length, s.point->value_bytes());
      }
      ++kinds[static_cast<std::size_t>(s.kind)];
      next += s.length;
    }
    EXPECT_EQ(next, r.length);
  }
  EXPECT_GT(kinds[static_cast<std::size_t>(RegisterStep::Kind::kValue)], 1000U);
  EXPECT_GT(kinds[static_cast<std::size_t>(RegisterStep::Kind::kPartial)], 100U);
  EXPECT_GT(kinds[static_cast<std::size_t>(RegisterStep::Kind::kSpare)], 10U);
  EXPECT_GT(kinds[static_cast<std::size_t>(RegisterStep::Kind::kUndefined)], 100U);
}

// Tables of 2, 16 and 64 slots (pairs): in the small ones nearly every range shares its slot
// with the ranges asked just before it, the same start with another length included.
TEST(RegisterPlans, RememberedSplitsAreTheUnrememberedOnesInAnyOrder) {
  const std::vector<SpaceRange> ranges = ranges_around_bundled_points();
  ASSERT_GT(ranges.size(), 1000U);  // far more than the default table holds
  std::vector<RegisterStep> expected;
  for (const unsigned slot_bits : {1U, 4U, 6U}) {
    RegisterPlans plans(slot_bits);
    for (std::size_t k = 0; k < 3 * ranges.size(); ++k) {
      const SpaceRange& r = ranges[asked_again_order(k, ranges.size())];
      plan_registers(*r.space, r.start, r.length, expected);
      EXPECT_TRUE(same_steps(expected, plans.of(*r.space, r.start, r.length)))
          << "range " << r.start << "+" << r.length << " bytes of space " << r.space->id
          << ", table of 2^" << slot_bits;
      EXPECT_TRUE(same_steps(expected, plans.of(*r.space, r.start, r.length)));
    }
  }
}

}  // namespace
}  // namespace rtu::dissect
