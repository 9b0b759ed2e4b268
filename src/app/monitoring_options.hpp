#pragma once
// Options of the commands that watch a bus for a long time (`live`, `demo`): metrics, the
// bus's name, the event log and health summaries.
#include <CLI/CLI.hpp>
#include <string>

#include "app/live_session.hpp"

namespace rtu::app {

struct MonitoringOptions {
  std::string metrics;
  std::string bus_name;  // its value when add_to() is called is the default shown
  std::string events;
  std::string summary_every;
  bool stop_on_write_error = false;

  void add_to(CLI::App& command);
  // Into the session; throws InputError naming the option for a bad --summary-every.
  void apply(LiveSessionSetup& session) const;
};

// "90s", "15m", "1h", "1d" → nanoseconds; throws InputError naming `option` otherwise.
Nanos parse_period(const std::string& text, std::string_view option);

}  // namespace rtu::app
