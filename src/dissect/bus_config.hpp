#pragma once
// What a bus file (--bus plant.toml) says: the line settings and which model each slave
// address is. Format in dissectors/README.md, section "Bus files".
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "serial/line_settings.hpp"

namespace rtu::dissect {

struct SlaveModel {
  std::uint8_t slave = 0;
  std::string model;
  // Where it was said ("plant.toml:7", "--device 2=yw2050"), for messages about the model.
  std::string origin;
};

// [live]: how `rtuscope live --bus FILE` watches this bus when the command line does not say
// (a service runs one bus per file). Values are checked where they are used, as the options
// of the same names are; empty = not given.
struct LiveConfig {
  std::vector<std::string> ports;   // one, or two for the two directions of a link
  std::string bus_name;             // --bus-name
  std::string write;                // -w
  std::string rotate;               // --rotate
  std::optional<std::size_t> keep;  // --keep
  std::string metrics;              // --metrics
  std::string events;               // --events
  std::string summary_every;        // --summary-every
  std::string report;               // --report
};

struct BusConfig {
  std::optional<std::uint32_t> baud;
  std::optional<Parity> parity;
  std::optional<std::uint8_t> stop_bits;
  std::optional<std::uint32_t> timeout_ms;
  std::vector<SlaveModel> slaves;
  LiveConfig live;
};

}  // namespace rtu::dissect
