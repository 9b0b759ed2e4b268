#pragma once
// A table of the formats of one kind (input captures, record outputs, reports, exports):
// each has the name the command line accepts, the file extensions that select it, and what
// makes it. The command line's choices and every dispatcher read the same table, so a
// format is added, renamed or given an extension in one place only.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rtu {

template <typename Factory>
struct FormatEntry {
  std::string_view name;                     // as the command line accepts it
  std::string_view description;              // for help texts ("" when none is shown)
  std::vector<std::string_view> extensions;  // with the dot: ".pcapng"
  Factory factory;
};

template <typename Factory>
using FormatTable = std::vector<FormatEntry<Factory>>;

// Whether extensions match whatever the case ("X.CSV") or only as written.
enum class ExtensionCase : std::uint8_t { kExact, kAnyCase };

// True when `path` ends with `extension`.
bool path_has_extension(std::string_view path, std::string_view extension, ExtensionCase rule);

// The entry called `name`, or null.
template <typename Factory>
const FormatEntry<Factory>* find_format(const FormatTable<Factory>& table, std::string_view name) {
  for (const auto& entry : table) {
    if (entry.name == name) return &entry;
  }
  return nullptr;
}

// The entry called `name`, else the table's first (its default). For dispatchers behind a
// command line that already refused other names.
template <typename Factory>
const FormatEntry<Factory>& find_format_or_default(const FormatTable<Factory>& table,
                                                   std::string_view name) {
  const auto* entry = find_format(table, name);
  return entry != nullptr ? *entry : table.front();
}

// The first entry one of whose extensions ends `path`, or null.
template <typename Factory>
const FormatEntry<Factory>* find_format_for_path(const FormatTable<Factory>& table,
                                                 std::string_view path, ExtensionCase rule) {
  for (const auto& entry : table) {
    for (const auto extension : entry.extensions) {
      if (path_has_extension(path, extension, rule)) return &entry;
    }
  }
  return nullptr;
}

// Every name, in table order (the command line's choices).
template <typename Factory>
std::vector<std::string> format_names(const FormatTable<Factory>& table) {
  std::vector<std::string> names;
  names.reserve(table.size());
  for (const auto& entry : table) names.emplace_back(entry.name);
  return names;
}

}  // namespace rtu
