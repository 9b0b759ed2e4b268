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
};

struct BusConfig {
  std::optional<std::uint32_t> baud;
  std::optional<Parity> parity;
  std::optional<std::uint8_t> stop_bits;
  std::optional<std::uint32_t> timeout_ms;
  std::vector<SlaveModel> slaves;
};

}  // namespace rtu::dissect
