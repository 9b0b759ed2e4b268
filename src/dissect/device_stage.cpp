#include "dissect/device_stage.hpp"

#include <array>
#include <cmath>
#include <cstdint>

#include "core/round_half_away.hpp"

namespace rtu::dissect {
namespace {

// A value to the point's decimals, as the decode output shows it (point_format.hpp); this
// also drops binary noise such as 22432.000000000004 from the exports.
double to_decimals(double value, int decimals) {
  // Exact powers of ten up to 10^22 (the same doubles std::pow gives), without a call per value.
  static constexpr std::array<double, 23> kPowersOfTen = {
      1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
      1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  const double scale = decimals >= 0 && decimals < static_cast<int>(kPowersOfTen.size())
                           ? kPowersOfTen[static_cast<std::size_t>(decimals)]
                           : std::pow(10.0, decimals);
  const double rounded = round_half_away(value * scale) / scale;
  return std::isfinite(rounded) ? rounded : value;
}

// Whole points with a value: addresses the map does not define, spare registers, points a
// transfer cuts in half and values whose scale nobody knows yet are left out.
void append_named(const Record& frame, const std::vector<DecodedPoint>& points,
                  std::vector<PointValue>& out) {
  for (const DecodedPoint& p : points) {
    if (p.point == nullptr || p.spare_index > 0 || p.partial || !p.has_value) continue;
    if (p.unknown_vars != 0) continue;
    // Filled in place: a PointValue built on the stack and then copied in was stored and
    // reloaded in pieces of different widths, which stalls the copy (the report's top cost).
    PointValue& v = out.emplace_back();
    v.t = frame.t_start;
    v.slave = frame.slave();
    v.point = p.point->name;
    v.value = to_decimals(p.value, p.point->decimals);
    v.unit = p.point->unit;
    v.key = reinterpret_cast<std::uintptr_t>(p.point);
    v.definition = p.point;
  }
}

}  // namespace

DeviceStage::DeviceStage(DeviceTable& table, RecordSink& next, bool collect_values)
    : table_(table), next_(next), collect_values_(collect_values) {}

void DeviceStage::on_record(Record& record) {
  if (record.kind != RecordKind::kFrame || record.size < 2) {
    next_.on_record(record);
    return;
  }
  if (record.role == Role::kRequest) {
    // Here, in place, not copied into reading_: it is needed only while the record is passed.
    const DataAccess access = data_access(record, nullptr);
    reading_.request_access = &access;
    decode_and_pass(record);
  } else {
    reading_.request_access = nullptr;
    decode_and_pass(record);
  }
  reading_.request_access = nullptr;
}

void DeviceStage::decode_and_pass(Record& record) {
  const std::uint8_t slave = record.slave();
  reading_.map = table_.map_of(slave);
  if (reading_.map != nullptr) {
    decoder_.decode(*reading_.map, table_.state(slave), record, reading_.request_access,
                    reading_.decoded);
    record.issues.merge(reading_.decoded.issues);
  } else {
    reading_.decoded.clear();
  }
  reading_.values.clear();
  if (collect_values_) collect_values(record);
  record.device = &reading_;
  next_.on_record(record);
  record.device = nullptr;
}

void DeviceStage::collect_values(const Record& frame) {
  if (reading_.map == nullptr) {
    raw_.collect(frame, reading_.values);
    return;
  }
  if (!carries_values(frame)) return;
  // A read's values are on its response; a write's are confirmed by it.
  append_named(frame, reading_.decoded.points, reading_.values);
  append_named(frame, reading_.decoded.confirmed, reading_.values);
}

}  // namespace rtu::dissect
