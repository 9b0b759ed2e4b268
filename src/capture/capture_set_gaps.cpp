#include "capture/capture_set_gaps.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <filesystem>
#include <vector>

#include "core/time_format.hpp"

namespace rtu {
namespace {

std::string seconds_text(Nanos t) {
  fmt::memory_buffer b;
  append_seconds(b, t, 3);
  return fmt::to_string(b);
}

std::string rotation_file(const RotationName& name, std::uint64_t number) {
  return fmt::format("{}-{:0{}}{}", name.stem, number, name.digits, name.extension);
}

// "site-0003.pcapng", "site-0003.pcapng to site-0005.pcapng (3 files)".
std::optional<std::string> skipped_numbers(const std::string& before, const std::string& after) {
  const auto a = parse_rotation_name(before);
  const auto b = parse_rotation_name(after);
  if (!a || !b || a->stem != b->stem || a->extension != b->extension) return std::nullopt;
  if (b->number <= a->number + 1) return std::nullopt;
  const std::uint64_t first = a->number + 1;
  const std::uint64_t last = b->number - 1;
  if (first == last) return rotation_file(*a, first);
  return fmt::format("{} to {} ({} files)", rotation_file(*a, first), rotation_file(*a, last),
                     last - first + 1);
}

}  // namespace

std::optional<RotationName> parse_rotation_name(const std::string& path) {
  const std::filesystem::path p(path);
  const std::string stem = p.stem().string();
  const std::size_t dash = stem.rfind('-');
  if (dash == std::string::npos || dash == 0 || dash + 1 == stem.size()) return std::nullopt;
  const std::string digits = stem.substr(dash + 1);
  // More than 18 digits would not fit; the recorder writes 4 (more past 9999 files).
  if (digits.size() > 18 || digits.find_first_not_of("0123456789") != std::string::npos) {
    return std::nullopt;
  }
  RotationName name;
  name.stem = (p.parent_path() / stem.substr(0, dash)).string();
  name.number = std::stoull(digits);
  name.digits = digits.size();
  name.extension = p.extension().string();
  return name;
}

std::optional<std::string> missing_file_warning(const SetBoundary& boundary) {
  std::vector<std::string> reasons;
  const std::optional<std::string> skipped = skipped_numbers(boundary.before, boundary.after);
  if (boundary.before_ended && !skipped) {
    return fmt::format(
        "{}: the recording stopped at the end of {} and started again {} s later: the bus "
        "was not recorded in between",
        boundary.after, boundary.before, seconds_text(boundary.silence));
  }
  if (skipped) {
    reasons.push_back(fmt::format("the rotation numbering skips {}", *skipped));
  }
  const Nanos usual = boundary.longest_within * kMissingSilenceFactor;
  if (boundary.silence > kMissingSilenceFloor && boundary.silence > usual) {
    reasons.push_back(fmt::format(
        "no record for {} s between them, over {} times the longest silence within either "
        "file ({} s)",
        seconds_text(boundary.silence), kMissingSilenceFactor,
        seconds_text(boundary.longest_within)));
  }
  if (reasons.empty()) return std::nullopt;
  return fmt::format("{}: a file seems to be missing before it (after {}): {}", boundary.after,
                     boundary.before, fmt::join(reasons, "; "));
}

}  // namespace rtu
