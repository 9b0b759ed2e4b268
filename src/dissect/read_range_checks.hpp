#pragma once
// What a read request's range says against a device map: addresses the map does not define,
// and a range that starts or ends inside a point. A master polls the same few ranges over
// and over, so the answers are remembered (a small table per decoder) instead of walking
// the map's points again for every request.
#include <cstdint>
#include <vector>

#include "core/issue.hpp"
#include "dissect/device_map.hpp"

namespace rtu::dissect {

// kUndefinedRegister and kPartialPoint, as a read of `quantity` from `start` in `space`
// earns them. The walk itself, unremembered.
IssueSet read_range_issues(const Space& space, std::uint32_t start, std::uint32_t quantity);

class ReadRangeChecks {
 public:
  // A table of 2^slot_bits answers (1 to 16 bits). The default is several times the ranges
  // a bus polls: a slot that two ranges share is walked again each time they alternate.
  explicit ReadRangeChecks(unsigned slot_bits = kDefaultSlotBits);

  // read_range_issues(), remembered by the space's address and the range. A Space must
  // outlive the checks that saw it: a later one at the same address would get its answers.
  IssueSet of(const Space& space, std::uint32_t start, std::uint32_t quantity);

 private:
  struct Entry {
    const Space* space = nullptr;
    std::uint32_t start = 0;
    std::uint32_t quantity = 0;
    IssueSet issues;
  };
  static constexpr unsigned kDefaultSlotBits = 8;

  unsigned slot_bits_;
  std::vector<Entry> entries_;
};

}  // namespace rtu::dissect
