#include "fuzz_oracle.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace rtu::fuzz {
namespace {

// Leading decimal digits of `s` as a number, and how many there were (0: none, or too many
// to be a line or an offset).
std::optional<std::uint64_t> leading_number(std::string_view& s) {
  std::size_t n = 0;
  std::uint64_t value = 0;
  while (n < s.size() && s[n] >= '0' && s[n] <= '9') {
    if (n == 19) return std::nullopt;
    value = value * 10 + static_cast<std::uint64_t>(s[n] - '0');
    ++n;
  }
  if (n == 0) return std::nullopt;
  s.remove_prefix(n);
  return value;
}

}  // namespace

void fail(std::string_view target, std::string_view what, std::string_view detail) {
  std::fprintf(stderr, "%.*s: %.*s: %.*s\n", static_cast<int>(target.size()), target.data(),
               static_cast<int>(what.size()), what.data(), static_cast<int>(detail.size()),
               detail.data());
  std::abort();
}

std::optional<Place> place_in_message(std::string_view message, std::string_view name) {
  if (message.substr(0, name.size()) != name) return std::nullopt;
  std::string_view rest = message.substr(name.size());
  constexpr std::string_view kOffset = ": offset ";
  Place place;
  if (rest.substr(0, kOffset.size()) == kOffset) {
    rest.remove_prefix(kOffset.size());
    place.kind = Place::Kind::kOffset;
  } else if (!rest.empty() && rest.front() == ':') {
    rest.remove_prefix(1);
    place.kind = Place::Kind::kLine;
  } else {
    return std::nullopt;
  }
  const auto number = leading_number(rest);
  if (!number || rest.empty() || rest.front() != ':') return std::nullopt;
  place.number = *number;
  return place;
}

void require_line(std::string_view target, std::string_view message, std::string_view name,
                  std::uint64_t max_line) {
  const auto place = place_in_message(message, name);
  if (!place || place->kind != Place::Kind::kLine) {
    fail(target, "error message names no line", message);
  }
  if (place->number < 1 || place->number > max_line) {
    fail(target, "error message names a line outside the input", message);
  }
}

void require_offset(std::string_view target, std::string_view message, std::string_view name,
                    std::uint64_t size) {
  const auto place = place_in_message(message, name);
  if (!place || place->kind != Place::Kind::kOffset) {
    fail(target, "error message names no offset", message);
  }
  if (place->number > size) {
    fail(target, "error message names an offset past the end of the input", message);
  }
}

std::uint64_t count_lines(std::string_view text) {
  const auto newlines = static_cast<std::uint64_t>(std::count(text.begin(), text.end(), '\n'));
  const bool unterminated = !text.empty() && text.back() != '\n';
  return std::max<std::uint64_t>(1, newlines + (unterminated ? 1 : 0));
}

}  // namespace rtu::fuzz
