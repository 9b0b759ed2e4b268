#pragma once
// Issue ids and sets. A *violation* (bytes that are not a frame) becomes a noise record;
// an issue is a *weird* on a record that is still shown. Keys come from issues.def only.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace rtu {

enum class Severity : std::uint8_t { kInfo, kWarning, kError };

enum class IssueId : std::uint8_t {
#define RTU_ISSUE(id, key, severity, summary) id,
#include "core/issues.def"
#undef RTU_ISSUE
  kCount
};

struct IssueInfo {
  IssueId id;
  std::string_view key;
  Severity severity;
  std::string_view summary;
};

std::span<const IssueInfo> issue_catalogue();
const IssueInfo& issue_info(IssueId id);
std::optional<IssueId> issue_from_key(std::string_view key);
std::string_view severity_name(Severity s);

// A small set of issues, iterated in catalogue order.
class IssueSet {
 public:
  static_assert(static_cast<unsigned>(IssueId::kCount) <= 64);
  void add(IssueId id) { bits_ |= bit(id); }
  void remove(IssueId id) { bits_ &= ~bit(id); }
  [[nodiscard]] bool has(IssueId id) const { return (bits_ & bit(id)) != 0; }
  [[nodiscard]] bool empty() const { return bits_ == 0; }
  [[nodiscard]] std::uint64_t bits() const { return bits_; }
  void merge(IssueSet other) { bits_ |= other.bits_; }

  // Calls fn(id) for every issue in the set, in catalogue order; only set bits cost a step
  // (most records have none).
  template <typename Fn>
  void for_each(Fn&& fn) const {
    for (std::uint64_t rest = bits_; rest != 0; rest &= rest - 1) {
      fn(static_cast<IssueId>(std::countr_zero(rest)));
    }
  }

 private:
  static std::uint64_t bit(IssueId id) { return std::uint64_t{1} << static_cast<unsigned>(id); }
  std::uint64_t bits_ = 0;
};

// How many records carried each issue: what reports count, one counter per key of the
// catalogue, so a new key is counted everywhere without a line of its own.
class IssueCounts {
 public:
  void add(IssueSet issues) {
    issues.for_each([this](IssueId id) { ++counts_[static_cast<unsigned>(id)]; });
  }
  void merge(const IssueCounts& other) {
    for (std::size_t i = 0; i < counts_.size(); ++i) counts_[i] += other.counts_[i];
  }
  [[nodiscard]] std::uint64_t operator[](IssueId id) const {
    return counts_[static_cast<unsigned>(id)];
  }
  // Calls fn(id, count) for every issue counted at least once, in catalogue order.
  template <typename Fn>
  void for_each(Fn&& fn) const {
    for (unsigned i = 0; i < counts_.size(); ++i) {
      if (counts_[i] != 0) fn(static_cast<IssueId>(i), counts_[i]);
    }
  }

 private:
  std::array<std::uint64_t, static_cast<unsigned>(IssueId::kCount)> counts_{};
};

}  // namespace rtu
