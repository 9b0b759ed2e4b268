#pragma once
// Reads device maps (dissectors/*.toml, format in dissectors/README.md) and bus files.
// This and sensor_classes.cpp are the only translation units that include toml++: it is
// heavy to compile.
#include <string>
#include <string_view>
#include <vector>

#include "dissect/bus_config.hpp"
#include "dissect/device_map.hpp"

namespace rtu::dissect {

struct MapLoadResult {
  DeviceMap map;                    // meaningful only when errors is empty
  std::vector<std::string> errors;  // each "file:line: what is wrong", in file order
  [[nodiscard]] bool ok() const { return errors.empty(); }
};

// Parses and checks a map. Every problem found is reported, not only the first: unknown
// keys, bad values, overlapping points, dangling references.
MapLoadResult load_map_text(std::string_view text, std::string_view file_name);
// As above from a file; a file that cannot be read is one error "file: cannot read".
MapLoadResult load_map_file(const std::string& path);

// Reads a bus file (line settings and slave → model). Throws InputError("file:line: ...").
BusConfig load_bus_file(const std::string& path);
BusConfig load_bus_text(std::string_view text, std::string_view file_name);

}  // namespace rtu::dissect
