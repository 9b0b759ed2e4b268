#include "app/monitoring_options.hpp"

#include <fmt/format.h>

#include <charconv>

#include "core/input_error.hpp"

namespace rtu::app {

void MonitoringOptions::add_to(CLI::App& command) {
  command.add_option("--metrics", metrics,
                     "Serve Prometheus metrics at http://ADDR:PORT/metrics (e.g. "
                     "127.0.0.1:9464; default: none)");
  command.add_option("--bus-name", bus_name,
                     "Name of the bus in metrics and events (default: the port's file name)");
  command.add_option("--events", events,
                     "Write events (timeouts, exceptions, line errors, findings, ports lost "
                     "and back, rotations, summaries) as JSON lines to FILE, or - for "
                     "standard output");
  command.add_option("--summary-every", summary_every,
                     "Every period (e.g. 15m), a health summary into the events and, with -w, "
                     "into the capture as a comment");
  command.add_flag("--stop-on-write-error", stop_on_write_error,
                   "When the recording (-w) cannot be written (a full disk), stop the run with "
                   "exit status 1 (default: the recording stops, decoding goes on)");
}

void MonitoringOptions::apply(LiveSessionSetup& session) const {
  session.metrics_address = metrics;
  session.bus_name = bus_name;
  session.events_path = events;
  session.stop_on_write_error = stop_on_write_error;
  if (!summary_every.empty())
    session.summary_every = parse_period(summary_every, "--summary-every");
}

Nanos parse_period(const std::string& text, std::string_view option) {
  std::uint64_t n = 0;
  const char* end = text.data() + text.size();
  const auto [unit_at, ec] = std::from_chars(text.data(), end, n);
  const std::string_view unit(unit_at, static_cast<std::size_t>(end - unit_at));
  Nanos scale = 0;
  if (unit == "s") scale = kNanosPerSecond;
  if (unit == "m" || unit == "min") scale = 60 * kNanosPerSecond;
  if (unit == "h") scale = 3600 * kNanosPerSecond;
  if (unit == "d") scale = 86400 * kNanosPerSecond;
  if (ec != std::errc() || n == 0 || n > 1'000'000 || scale == 0) {
    throw InputError(
        fmt::format("{}: expected a period such as 90s, 15m, 1h or 1d, found '{}'", option, text));
  }
  return static_cast<Nanos>(n) * scale;
}

}  // namespace rtu::app
