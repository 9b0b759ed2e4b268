#include "dissect/device_point_source.hpp"

#include <cmath>

#include "modbus/data_access.hpp"

namespace rtu::dissect {
namespace {

// A value to the point's decimals, as the decode output shows it (point_format.hpp); this
// also drops binary noise such as 22432.000000000004 from the exports.
double to_decimals(double value, int decimals) {
  const double scale = std::pow(10.0, decimals);
  const double rounded = std::round(value * scale) / scale;
  return std::isfinite(rounded) ? rounded : value;
}

}  // namespace

void DevicePointSource::assign(std::uint8_t slave, const DeviceMap& map, ModelOrigin origin) {
  Slave& s = slaves_[slave];
  s.map = &map;
  s.origin = origin;
  s.state.reset(map);
}

void DevicePointSource::assign_identified(const std::vector<SlaveRanking>& ranking) {
  for (const SlaveRanking& r : ranking) {
    if (slaves_[r.slave].map != nullptr) continue;  // configured (or identified) already
    if (const DeviceMap* map = confident_map(r)) assign(r.slave, *map, ModelOrigin::kIdentified);
  }
}

std::string_view DevicePointSource::device_model(std::uint8_t slave) const {
  const DeviceMap* map = slaves_[slave].map;
  return map == nullptr ? std::string_view{} : std::string_view(map->model);
}

bool DevicePointSource::device_model_identified(std::uint8_t slave) const {
  return slaves_[slave].map != nullptr && slaves_[slave].origin == ModelOrigin::kIdentified;
}

std::string_view DevicePointSource::device_exception_name(std::uint8_t slave,
                                                          std::uint8_t code) const {
  const DeviceMap* map = slaves_[slave].map;
  return map == nullptr ? std::string_view{} : map->exception_name(code);
}

void DevicePointSource::extract(const Record& frame, PointSink& sink) {
  if (frame.kind != RecordKind::kFrame || frame.size < 4) return;
  Slave& slave = slaves_[frame.slave()];
  if (slave.map == nullptr) {
    if (fallback_ != nullptr) fallback_->extract(frame, sink);
    return;
  }
  // Values only from a normal response to a request of the same slave and function, with
  // both CRCs good and byte counts that fit (as the raw source demands).
  if (!frame.crc_ok || frame.role != Role::kResponse || frame.request == nullptr ||
      frame.is_exception() || !frame.request->crc_ok) {
    return;
  }
  const Record& request = *frame.request;
  if (request.slave() != frame.slave() || request.function() != frame.function()) return;
  if (frame.issues.has(IssueId::kByteCount) || request.issues.has(IssueId::kByteCount)) return;

  if (data_access(request, nullptr).write() == nullptr) {
    decoder_.decode(*slave.map, slave.state, frame, decoded_);
    deliver(frame, decoded_, sink);
    return;
  }
  // The response confirms the write: learn from it first (a confirmed PT write scales what
  // follows), then take the written values from the request.
  decoder_.decode(*slave.map, slave.state, frame, learned_);
  decoder_.decode(*slave.map, slave.state, request, decoded_);
  deliver(frame, decoded_, sink);
}

void DevicePointSource::deliver(const Record& frame, const Decoded& decoded,
                                PointSink& sink) const {
  for (const DecodedPoint& p : decoded.points) {
    if (p.point == nullptr || p.spare_index > 0 || p.partial || !p.has_value) continue;
    if (p.unknown_vars != 0) continue;  // a scale nobody knows yet: no honest value
    PointSample s;
    s.t = frame.t_start;
    s.slave = frame.slave();
    s.point = p.point->name;
    s.value = to_decimals(p.value, p.point->decimals);
    s.unit = p.point->unit;
    sink.on_point(s);
  }
}

}  // namespace rtu::dissect
