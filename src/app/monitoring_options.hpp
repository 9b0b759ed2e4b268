#pragma once
// Options of the commands that watch a bus for a long time (`live`, `demo`): where to serve
// metrics and what the bus is called in them.
#include <CLI/CLI.hpp>
#include <string>

namespace rtu::app {

// Adds --metrics ADDR:PORT and --bus-name NAME to `command`, stored in `metrics` and
// `bus_name` (whose current value is the default shown).
void add_monitoring_options(CLI::App& command, std::string& metrics, std::string& bus_name);

}  // namespace rtu::app
