#include "dissect/device_table.hpp"

#include <algorithm>

namespace rtu::dissect {

void DeviceTable::assign(std::uint8_t slave, const DeviceMap& map, ModelOrigin origin) {
  Row& row = rows_[slave];
  row.map = &map;
  row.origin = origin;
  row.state.reset(map);
}

void DeviceTable::assign_identified(const std::vector<SlaveRanking>& ranking) {
  for (const SlaveRanking& r : ranking) {
    if (rows_[r.slave].map != nullptr) continue;  // configured (or identified) already
    if (const DeviceMap* map = confident_map(r)) assign(r.slave, *map, ModelOrigin::kIdentified);
  }
}

std::string_view DeviceTable::model(std::uint8_t slave) const {
  const DeviceMap* map = rows_[slave].map;
  return map == nullptr ? std::string_view{} : std::string_view(map->model);
}

bool DeviceTable::identified(std::uint8_t slave) const {
  return rows_[slave].map != nullptr && rows_[slave].origin == ModelOrigin::kIdentified;
}

std::string_view DeviceTable::exception_name(std::uint8_t slave, std::uint8_t code) const {
  const DeviceMap* map = rows_[slave].map;
  return map == nullptr ? std::string_view{} : map->exception_name(code);
}

bool DeviceTable::empty() const {
  return std::none_of(rows_.begin(), rows_.end(), [](const Row& r) { return r.map != nullptr; });
}

}  // namespace rtu::dissect
