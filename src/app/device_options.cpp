#include "app/device_options.hpp"

#include <fmt/format.h>

#include "core/input_error.hpp"
#include "dissect/map_loader.hpp"

namespace rtu::app {
namespace {

void throw_map_errors(const std::vector<std::string>& errors) {
  if (errors.empty()) return;
  std::string message = "device maps with errors:";
  for (const auto& e : errors) message += "\n  " + e;
  throw InputError(message);
}

std::uint8_t parse_slave(const std::string& text, const std::string& where) {
  unsigned value = 0;
  bool ok = !text.empty() && text.size() <= 3;
  for (const char c : text) {
    if (c < '0' || c > '9') ok = false;
    value = value * 10U + static_cast<unsigned>(c - '0');
  }
  if (!ok || value < 1 || value > 247) {
    throw InputError(fmt::format("{}: expected a slave address 1..247, found '{}'", where, text));
  }
  return static_cast<std::uint8_t>(value);
}

}  // namespace

void DeviceOptions::add_to(CLI::App& command) {
  command_ = &command;
  command.add_option("--device", devices,
                     "Slave ADDR is device MODEL (e.g. 1=yw2050); repeatable. Models: the "
                     "bundled maps and --dissectors maps");
  command
      .add_option("--bus", bus_file,
                  "Bus file (TOML): [line] settings and [slaves] ADDR = \"MODEL\"")
      ->check(CLI::ExistingFile);
  command
      .add_option("--dissectors", dissector_dirs,
                  "Folder of user device maps (*.toml), added to the bundled ones")
      ->check(CLI::ExistingDirectory);
}

std::unique_ptr<DeviceSetup> DeviceOptions::load_maps(const std::vector<std::string>& extra_dirs) {
  auto setup = std::make_unique<DeviceSetup>();
  const std::string bundled = dissect::MapLibrary::bundled_dir();
  if (!bundled.empty()) throw_map_errors(setup->library.load_dir(bundled));
  for (const auto& dir : extra_dirs) throw_map_errors(setup->library.load_dir(dir));
  return setup;
}

std::unique_ptr<DeviceSetup> DeviceOptions::build(ReplayOptions& options) const {
  if (devices.empty() && bus_file.empty()) return nullptr;
  auto setup = load_maps(dissector_dirs);
  std::vector<dissect::SlaveModel> slaves;
  if (!bus_file.empty()) {
    const dissect::BusConfig bus = dissect::load_bus_file(bus_file);
    // The command line wins over the bus file, which wins over the capture's own header.
    if (!options.overrides.baud) options.overrides.baud = bus.baud;
    if (!options.overrides.parity) options.overrides.parity = bus.parity;
    if (!options.overrides.stop_bits) options.overrides.stop_bits = bus.stop_bits;
    const CLI::Option* timeout =
        command_ != nullptr ? command_->get_option_no_throw("--timeout-ms") : nullptr;
    const bool timeout_given = timeout != nullptr && timeout->count() > 0;
    if (bus.timeout_ms && !timeout_given) {
      options.response_timeout = static_cast<Nanos>(*bus.timeout_ms) * kNanosPerMilli;
      options.response_timeout_set = true;
    }
    slaves = bus.slaves;
  }
  for (const auto& d : devices) {
    const auto eq = d.find('=');
    if (eq == std::string::npos) {
      throw InputError(fmt::format("--device {}: expected ADDR=MODEL, e.g. 1=yw2050", d));
    }
    slaves.push_back(
        {parse_slave(d.substr(0, eq), "--device " + d), d.substr(eq + 1), "--device " + d});
  }
  for (const auto& s : slaves) {
    const dissect::DeviceMap* map = setup->library.find(s.model);
    if (map == nullptr) {
      throw InputError(fmt::format("{}: slave {}: no device map for model '{}' (known: {})",
                                   s.origin, s.slave, s.model, setup->library.model_list()));
    }
    setup->table.assign(s.slave, *map, dissect::ModelOrigin::kConfigured);
  }
  return setup;
}

std::unique_ptr<DeviceSetup> DeviceOptions::build_with_maps(ReplayOptions& options) const {
  auto setup = build(options);
  return setup ? std::move(setup) : load_maps(dissector_dirs);
}

}  // namespace rtu::app
