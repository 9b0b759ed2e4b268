#include "dissect/sensor_classes.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/input_error.hpp"
#include "dissect/map_library.hpp"

namespace rtu::dissect {
namespace {

std::string where(std::string_view file, const toml::node& node) {
  return fmt::format("{}:{}", file, node.source().begin.line);
}

}  // namespace

bool is_state_class(std::string_view text) {
  return text == "measurement" || text == "total" || text == "total_increasing";
}

SensorClasses SensorClasses::load_text(std::string_view text, std::string_view file_name) {
  toml::table root;
  try {
    root = toml::parse(text, file_name);
  } catch (const toml::parse_error& e) {
    throw InputError(
        fmt::format("{}:{}: {}", file_name, e.source().begin.line, std::string(e.description())));
  }
  SensorClasses classes;
  for (const auto& [key, node] : root) {
    if (key.str() != "unit" || !node.is_table()) {
      throw InputError(fmt::format("{}: unknown key '{}' (expected [unit.\"...\"] tables)",
                                   where(file_name, node), key.str()));
    }
    for (const auto& [unit, entry] : *node.as_table()) {
      const auto* table = entry.as_table();
      if (table == nullptr) {
        throw InputError(
            fmt::format("{}: unit.\"{}\" must be a table", where(file_name, entry), unit.str()));
      }
      SensorClass sensor;
      for (const auto& [field, value] : *table) {
        const auto text_value = value.value<std::string>();
        if (!text_value) {
          throw InputError(
              fmt::format("{}: {} must be a string", where(file_name, value), field.str()));
        }
        if (field.str() == "device_class") {
          sensor.device_class = *text_value;
        } else if (field.str() == "state_class") {
          sensor.state_class = *text_value;
        } else {
          throw InputError(fmt::format("{}: unknown key '{}' (expected device_class, state_class)",
                                       where(file_name, value), field.str()));
        }
      }
      if (!is_state_class(sensor.state_class)) {
        throw InputError(fmt::format(
            "{}: unit.\"{}\": state_class must be measurement, total or total_increasing",
            where(file_name, entry), unit.str()));
      }
      classes.by_unit_.emplace(std::string(unit.str()), std::move(sensor));
    }
  }
  return classes;
}

SensorClasses SensorClasses::load_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot read", path));
  std::ostringstream text;
  text << in.rdbuf();
  return load_text(text.str(), path);
}

std::string SensorClasses::bundled_path() {
  const std::string maps = MapLibrary::bundled_dir();
  if (maps.empty()) return {};
  const auto path = std::filesystem::path(maps) / "home_assistant" / "sensor_classes.toml";
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec) ? path.string() : std::string();
}

const SensorClass* SensorClasses::for_unit(std::string_view unit) const {
  const auto it = by_unit_.find(unit);
  return it == by_unit_.end() ? nullptr : &it->second;
}

}  // namespace rtu::dissect
