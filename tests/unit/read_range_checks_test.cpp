// A read range's issues against a map are remembered per decoder: the remembered answer is
// always the walk's, for every bundled map's spaces and ranges asked in any order, in tables
// of any size (ranges that share a slot replace each other), and the walk itself finds
// undefined addresses and cut points where the maps have them.
#include "dissect/read_range_checks.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "dissect_test_support.hpp"

namespace rtu::dissect {
namespace {

using testing::asked_again_order;
using testing::ranges_around_bundled_points;
using testing::SpaceRange;

TEST(ReadRangeChecks, TheWalkFindsUndefinedAddressesAndCutPointsAndCleanRanges) {
  std::size_t undefined = 0;
  std::size_t partial = 0;
  std::size_t clean = 0;
  for (const SpaceRange& r : ranges_around_bundled_points()) {
    const IssueSet issues = read_range_issues(*r.space, r.start, r.length);
    if (issues.has(IssueId::kUndefinedRegister)) ++undefined;
    if (issues.has(IssueId::kPartialPoint)) ++partial;
    if (issues.empty()) ++clean;
  }
  EXPECT_GT(undefined, 100U);
  EXPECT_GT(partial, 100U);
  EXPECT_GT(clean, 100U);
}

// Tables of 2, 16 and 256 slots: in the small ones nearly every range shares its slot with
// the range asked just before it, the same start with another quantity included.
TEST(ReadRangeChecks, RememberedAnswersAreTheWalksInAnyOrder) {
  const std::vector<SpaceRange> ranges = ranges_around_bundled_points();
  ASSERT_GT(ranges.size(), 1000U);  // far more than the default table holds
  for (const unsigned slot_bits : {1U, 4U, 8U}) {
    ReadRangeChecks checks(slot_bits);
    for (std::size_t k = 0; k < 3 * ranges.size(); ++k) {
      const SpaceRange& r = ranges[asked_again_order(k, ranges.size())];
      const IssueSet expected = read_range_issues(*r.space, r.start, r.length);
      EXPECT_EQ(checks.of(*r.space, r.start, r.length).bits(), expected.bits())
          << "range " << r.start << "+" << r.length << " of space " << r.space->id
          << ", table of 2^" << slot_bits;
      EXPECT_EQ(checks.of(*r.space, r.start, r.length).bits(), expected.bits());
    }
  }
}

}  // namespace
}  // namespace rtu::dissect
