#include "dissect/device_annotator.hpp"

#include <algorithm>

#include "dissect/point_format.hpp"

namespace rtu::dissect {

void DeviceAnnotator::assign(std::uint8_t slave, const DeviceMap& map) {
  slaves_[slave].map = &map;
  slaves_[slave].state.reset(map);
}

bool DeviceAnnotator::empty() const {
  return std::none_of(slaves_.begin(), slaves_.end(),
                      [](const Slave& s) { return s.map != nullptr; });
}

void DeviceAnnotator::annotate(Record& frame) {
  if (frame.kind != RecordKind::kFrame || frame.size < 2) return;
  Slave& slave = slaves_[frame.slave()];
  if (slave.map == nullptr) return;
  Slot& slot = slots_[frame.seq % slots_.size()];
  slot.seq = frame.seq;
  decoder_.decode(*slave.map, slave.state, frame, slot.decoded);
  frame.issues.merge(slot.decoded.issues);
}

const Decoded* DeviceAnnotator::decoded(const Record& frame) const {
  const Slot& slot = slots_[frame.seq % slots_.size()];
  if (!slot.seq || *slot.seq != frame.seq || slot.decoded.map == nullptr) return nullptr;
  return &slot.decoded;
}

void DeviceAnnotator::write_json(JsonWriter& json, const Record& frame) const {
  const Decoded* d = decoded(frame);
  if (d == nullptr) return;
  json.field("device", std::string_view(d->map->model));
  if (!d->points.empty()) write_points_json(json, *d);
}

void DeviceAnnotator::append_text(fmt::memory_buffer& out, const Record& frame) const {
  const Decoded* d = decoded(frame);
  if (d == nullptr) return;
  append_points_text(out, *d);
}

std::string_view DeviceAnnotator::exception_name(const Record& frame, std::uint8_t code) const {
  if (frame.size < 1) return {};
  const DeviceMap* map = slaves_[frame.slave()].map;
  return map == nullptr ? std::string_view{} : map->exception_name(code);
}

}  // namespace rtu::dissect
