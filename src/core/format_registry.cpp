#include "core/format_registry.hpp"

namespace rtu {

bool path_has_extension(std::string_view path, std::string_view extension, ExtensionCase rule) {
  if (path.size() < extension.size()) return false;
  const std::string_view tail = path.substr(path.size() - extension.size());
  if (rule == ExtensionCase::kExact) return tail == extension;
  for (std::size_t i = 0; i < tail.size(); ++i) {
    char c = tail[i];
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c + ('a' - 'A'));
    char e = extension[i];
    if (e >= 'A' && e <= 'Z') e = static_cast<char>(e + ('a' - 'A'));
    if (c != e) return false;
  }
  return true;
}

}  // namespace rtu
