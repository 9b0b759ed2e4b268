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

struct Range {
  const Space* space;
  std::uint32_t start;
  std::uint32_t quantity;
};

// Ranges around every point of every bundled map's spaces: starting before, at, inside and
// after each point, one to 24 units long.
std::vector<Range> ranges_of_bundled_maps() {
  std::vector<Range> ranges;
  for (const auto& map : testing::bundled_maps().maps()) {
    for (const Space& space : map->spaces) {
      for (const Point& p : space.points) {
        for (std::uint32_t back = 0; back <= 2; ++back) {
          if (p.addr < back) continue;
          for (std::uint32_t quantity = 1; quantity <= 24; ++quantity) {
            ranges.push_back({&space, p.addr - back, quantity});
            ranges.push_back({&space, p.addr + back + 1, quantity});
          }
        }
      }
    }
  }
  return ranges;
}

TEST(ReadRangeChecks, TheWalkFindsUndefinedAddressesAndCutPointsAndCleanRanges) {
  std::size_t undefined = 0;
  std::size_t partial = 0;
  std::size_t clean = 0;
  for (const Range& r : ranges_of_bundled_maps()) {
    const IssueSet issues = read_range_issues(*r.space, r.start, r.quantity);
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
  const std::vector<Range> ranges = ranges_of_bundled_maps();
  ASSERT_GT(ranges.size(), 1000U);  // far more than the default table holds
  for (const unsigned slot_bits : {1U, 4U, 8U}) {
    ReadRangeChecks checks(slot_bits);
    // Forwards, backwards, then every seventh: each range asked again after others.
    for (int pass = 0; pass < 3; ++pass) {
      for (std::size_t k = 0; k < ranges.size(); ++k) {
        const std::size_t i = pass == 0   ? k
                              : pass == 1 ? ranges.size() - 1 - k
                                          : (k * 7) % ranges.size();
        const Range& r = ranges[i];
        const IssueSet expected = read_range_issues(*r.space, r.start, r.quantity);
        EXPECT_EQ(checks.of(*r.space, r.start, r.quantity).bits(), expected.bits())
            << "range " << r.start << "+" << r.quantity << " of space " << r.space->id
            << ", table of 2^" << slot_bits;
        EXPECT_EQ(checks.of(*r.space, r.start, r.quantity).bits(), expected.bits());
      }
    }
  }
}

}  // namespace
}  // namespace rtu::dissect
