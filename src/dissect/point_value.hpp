#pragma once
// One value a frame tells about a slave's data: a device map's point ("Ua" = 229.8 V) or,
// for a slave without a map, a raw register or bit ("holding 0x0032" = 22980). Reports
// follow these over time and the CSV export lists them; neither cares where they came from.
#include <cstdint>
#include <string_view>

#include "core/time.hpp"

namespace rtu::dissect {

struct Point;  // device_map.hpp

struct PointValue {
  Nanos t = 0;  // start of the frame that carried the value
  std::uint8_t slave = 0;
  std::string_view point;  // valid while the record it hangs on is
  double value = 0.0;
  std::string_view unit;  // empty for raw values
  // Which point of its slave this is, for fast lookups: equal keys mean equal names (a raw
  // table and address, or the device map's point definition). 0 = not known.
  std::uint64_t key = 0;
  // The device map's definition of a named point (classes for MQTT discovery); null for raw
  // values.
  const Point* definition = nullptr;
};

// The key of a raw value: the table's number and the address, with a bit no pointer sets.
constexpr std::uint64_t raw_point_key(unsigned table, std::uint32_t addr) {
  return (std::uint64_t{1} << 63U) | (std::uint64_t{table} << 32U) | addr;
}

}  // namespace rtu::dissect
