#pragma once
// Options of every command that outputs frames, telling rtuscope which device model each
// slave is: --device ADDR=MODEL (repeatable), --bus FILE.toml (line settings and slaves),
// --dissectors DIR (user maps added to the bundled ones). See dissectors/README.md.
#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "dissect/device_table.hpp"
#include "dissect/map_library.hpp"
#include "pipeline/replay.hpp"

namespace rtu::app {

// The maps and the table of which slave is which model, kept together (the table points
// into the library).
struct DeviceSetup {
  dissect::MapLibrary library;
  dissect::DeviceTable table;
};

struct DeviceOptions {
  std::vector<std::string> devices;  // "ADDR=MODEL"
  std::string bus_file;
  std::vector<std::string> dissector_dirs;

  void add_to(CLI::App& command);
  // Loads the maps (bundled, then each --dissectors folder). Throws InputError for a map
  // with errors (every "file:line: what" in the message).
  [[nodiscard]] static std::unique_ptr<DeviceSetup> load_maps(
      const std::vector<std::string>& extra_dirs);
  // Loads the maps and the bus file, fills in the line settings the command line left
  // open, and assigns models to slaves. Null when no slave is named: plain Modbus output.
  // Throws InputError for a bad ADDR=MODEL, an unknown model or a bad bus file.
  [[nodiscard]] std::unique_ptr<DeviceSetup> build(ReplayOptions& options) const;
  // As build(), but with the maps loaded even when no slave is named: reports name the slaves
  // they identify.
  [[nodiscard]] std::unique_ptr<DeviceSetup> build_with_maps(ReplayOptions& options) const;

 private:
  CLI::App* command_ = nullptr;
};

}  // namespace rtu::app
