#include "app/monitoring_options.hpp"

namespace rtu::app {

void add_monitoring_options(CLI::App& command, std::string& metrics, std::string& bus_name) {
  command.add_option("--metrics", metrics,
                     "Serve Prometheus metrics at http://ADDR:PORT/metrics (e.g. "
                     "127.0.0.1:9464; default: none)");
  command.add_option("--bus-name", bus_name,
                     "Name of the bus in metrics (default: the port's file name)");
}

}  // namespace rtu::app
