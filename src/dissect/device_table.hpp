#pragma once
// Which device model each slave is, where that came from, and what has been learned about
// it from the traffic (PT and CT ratios): one row per slave address. The device stage
// decodes with it; reports ask it for models and vendor exception names.
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "dissect/device_map.hpp"
#include "dissect/map_identifier.hpp"
#include "dissect/register_decoder.hpp"

namespace rtu::dissect {

// Where a slave's model came from.
enum class ModelOrigin : std::uint8_t {
  kConfigured,  // --device, --bus
  kIdentified,  // ranked first by the MapIdentifier, confidently
};

class DeviceTable {
 public:
  // `map` must outlive the table (MapLibrary keeps maps at stable addresses). Forgets what
  // was learned about the slave.
  void assign(std::uint8_t slave, const DeviceMap& map, ModelOrigin origin);
  // Gives every slave without a map the one `ranking` names with confidence (confident_map),
  // as identified. Configured slaves keep theirs.
  void assign_identified(const std::vector<SlaveRanking>& ranking);

  [[nodiscard]] const DeviceMap* map_of(std::uint8_t slave) const { return rows_[slave].map; }
  [[nodiscard]] ModelOrigin origin_of(std::uint8_t slave) const { return rows_[slave].origin; }
  // The model's name ("YW2050"), or empty when the slave has no map.
  [[nodiscard]] std::string_view model(std::uint8_t slave) const;
  [[nodiscard]] bool identified(std::uint8_t slave) const;
  // The device's own meaning of an exception code (a vendor table, e.g. YAKOTEC's 01 = CRC
  // error), or empty where the standard meaning applies.
  [[nodiscard]] std::string_view exception_name(std::uint8_t slave, std::uint8_t code) const;
  [[nodiscard]] bool empty() const;

  // What has been learned about the slave (its map's vars); the device stage updates it.
  [[nodiscard]] SlaveState& state(std::uint8_t slave) { return rows_[slave].state; }

 private:
  struct Row {
    const DeviceMap* map = nullptr;
    ModelOrigin origin = ModelOrigin::kConfigured;
    SlaveState state;
  };
  std::array<Row, 256> rows_{};
};

}  // namespace rtu::dissect
