#include "capture/found_text.hpp"

#include <fmt/format.h>

namespace rtu {

std::string found_text(std::string_view text) {
  if (text.empty()) return "end of line";
  constexpr std::size_t kMaxShown = 24;
  std::string out = "'";
  for (std::size_t i = 0; i < text.size() && i < kMaxShown; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\t') {
      out += "\\t";
    } else if (c < 0x20U || c >= 0x7FU) {
      out += fmt::format("\\x{:02x}", c);
    } else {
      out += static_cast<char>(c);
    }
  }
  if (text.size() > kMaxShown) out += "...";
  out += '\'';
  return out;
}

std::string_view word_at(std::string_view line, std::size_t pos, char stop) {
  std::size_t end = pos;
  while (end < line.size() && line[end] != ' ' && line[end] != '\t' &&
         (stop == '\0' || line[end] != stop)) {
    ++end;
  }
  return pos < line.size() ? line.substr(pos, end - pos) : std::string_view{};
}

}  // namespace rtu
