#include "core/issue.hpp"

#include <array>

namespace rtu {
namespace {

constexpr std::array kCatalogue = {
#define RTU_ISSUE(id, key, severity, summary) \
  IssueInfo{IssueId::id, key, Severity::severity, summary},
#include "core/issues.def"
#undef RTU_ISSUE
};
static_assert(kCatalogue.size() == static_cast<std::size_t>(IssueId::kCount));

}  // namespace

std::span<const IssueInfo> issue_catalogue() {
  return kCatalogue;
}

const IssueInfo& issue_info(IssueId id) {
  return kCatalogue.at(static_cast<std::size_t>(id));
}

std::optional<IssueId> issue_from_key(std::string_view key) {
  for (const auto& info : kCatalogue) {
    if (info.key == key) return info.id;
  }
  return std::nullopt;
}

std::string_view severity_name(Severity s) {
  switch (s) {
    case Severity::kInfo: return "info";
    case Severity::kWarning: return "warning";
    case Severity::kError: return "error";
  }
  return "?";
}

}  // namespace rtu
