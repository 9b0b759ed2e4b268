#include "report/mqtt_feed.hpp"

#include <fmt/format.h>

#include "core/json_writer.hpp"
#include "core/time_format.hpp"
#include "dissect/device_map.hpp"
#include "dissect/device_stage.hpp"

namespace rtu {
namespace {

// "2026-11-30T10:00:00.123Z", or seconds for capture-relative times.
void time_value(JsonWriter& json, fmt::memory_buffer& scratch, Nanos t) {
  if (t < kWallClockFrom) {
    json.value_fixed(to_seconds(t), 3);
    return;
  }
  scratch.clear();
  append_utc_date(scratch, t);
  scratch.push_back('T');
  append_utc_time_of_day(scratch, t, 3);
  scratch.push_back('Z');
  json.value(std::string_view(scratch.data(), scratch.size()));
}

std::string text_of(const fmt::memory_buffer& buffer) {
  return {buffer.data(), buffer.size()};
}

}  // namespace

std::string mqtt_id(std::string_view text) {
  std::string id;
  for (const char c : text) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       c == '_' || c == '-';
    id.push_back(plain ? c : '_');
  }
  return id.empty() ? std::string("_") : id;
}

std::string mqtt_base_topic(std::string_view bus) {
  return fmt::format("rtuscope/{}", mqtt_id(bus));
}

MqttFeed::MqttFeed(MqttFeedOptions options, Publish publish)
    : options_(std::move(options)),
      publish_(std::move(publish)),
      base_(mqtt_base_topic(options_.bus)) {}

void MqttFeed::on_record(Record& record) {
  const Nanos now = record.t_start;
  last_t_ = std::max(last_t_, record.t_end);
  if (record.kind == RecordKind::kNoise) {
    ++noise_;
  } else {
    ++frames_;
    const std::uint8_t slave = record.slave();
    if (record.issues.has(IssueId::kCrc)) ++crc_errors_;
    if (record.issues.has(IssueId::kTimeout)) ++timeouts_;
    if (slave != 0 && !record.issues.has(IssueId::kCrc)) {
      SlaveState& state = slaves_[slave];
      if (record.role == Role::kResponse) {
        state.timeouts_in_a_row = 0;
        slave_status(slave, true);
      } else if (record.role == Role::kRequest && record.issues.has(IssueId::kTimeout) &&
                 ++state.timeouts_in_a_row >= options_.offline_after) {
        slave_status(slave, false);
      }
    }
    record.issues.for_each([&](IssueId id) {
      if (!findings_seen_.insert({slave, id}).second) return;
      fmt::memory_buffer payload;
      fmt::memory_buffer scratch;
      JsonWriter json(payload);
      json.begin_object();
      json.field("slave", static_cast<unsigned>(slave));
      json.field("issue", issue_info(id).key);
      json.field("summary", issue_info(id).summary);
      json.key("time");
      time_value(json, scratch, now);
      json.end_object();
      publish_({base_ + "/findings", text_of(payload), false});
    });
    // Named points only: raw registers of a slave without a map mean nothing to a user.
    if (record.device != nullptr && record.device->map != nullptr) {
      for (const auto& value : record.device->values) {
        point_value(record, value);
      }
    }
  }
  // Held-back changes are looked at every 100 ms of capture time, not on every record.
  if (now - last_due_check_ >= 100 * kNanosPerMilli) {
    last_due_check_ = now;
    send_due(now);
  }
  if (last_health_ == kUnknownTime) last_health_ = now;
  if (now - last_health_ >= options_.health_period) send_health(now);
}

void MqttFeed::on_finish() {
  for (auto& [topic, point] : points_) {
    if (point.pending) send_value(point);
  }
  send_health(last_t_);
}

void MqttFeed::slave_status(std::uint8_t slave, bool online) {
  SlaveState& state = slaves_[slave];
  if (state.known && state.online == online) return;
  state.known = true;
  state.online = online;
  publish_({fmt::format("{}/{}/status", base_, slave), online ? "online" : "offline", true});
}

void MqttFeed::point_value(const Record& record, const dissect::PointValue& sample) {
  const std::uint8_t slave = record.slave();
  const std::string topic = fmt::format("{}/{}/{}", base_, slave, mqtt_id(sample.point));
  const double value = sample.value;
  auto it = points_.find(topic);
  if (it == points_.end()) {
    PointState state;
    state.topic = topic;
    state.unit = std::string(sample.unit);
    if (record.device->map != nullptr) state.model = record.device->map->model;
    it = points_.emplace(topic, std::move(state)).first;
    if (options_.discovery) send_discovery(slave, sample, it->second, record);
  }
  PointState& state = it->second;
  state.value = value;
  state.value_at = record.t_start;
  if (state.sent_once && state.sent == value) {
    state.pending = false;  // back where it was: nothing to tell
    return;
  }
  state.pending = true;
  if (!state.sent_once || record.t_start - state.sent_at >= options_.min_interval) {
    send_value(state);
  }
}

void MqttFeed::send_value(PointState& point) {
  fmt::memory_buffer payload;
  fmt::memory_buffer scratch;
  JsonWriter json(payload);
  json.begin_object();
  json.key("value");
  json.value_double(point.value);
  json.field("unit", std::string_view(point.unit));
  json.key("time");
  time_value(json, scratch, point.value_at);
  if (!point.model.empty()) json.field("model", std::string_view(point.model));
  json.end_object();
  publish_({point.topic, text_of(payload), false});
  point.sent_once = true;
  point.sent = point.value;
  point.sent_at = point.value_at;
  point.pending = false;
}

void MqttFeed::send_due(Nanos now) {
  for (auto& [topic, point] : points_) {
    if (point.pending && now - point.sent_at >= options_.min_interval) send_value(point);
  }
}

void MqttFeed::send_discovery(std::uint8_t slave, const dissect::PointValue& sample,
                              const PointState& state, const Record& record) {
  const std::string_view point = sample.point;
  const std::string bus = mqtt_id(options_.bus);
  const std::string device_id = fmt::format("rtuscope_{}_{}", bus, slave);
  const std::string object_id = mqtt_id(point);
  const dissect::DeviceMap* map = record.device->map;
  fmt::memory_buffer payload;
  JsonWriter json(payload);
  json.begin_object();
  json.field("name", point);
  json.field("state_topic", std::string_view(state.topic));
  json.field("unique_id", std::string_view(fmt::format("{}_{}", device_id, object_id)));
  json.field("value_template", "{{ value_json.value }}");
  if (!state.unit.empty()) json.field("unit_of_measurement", std::string_view(state.unit));
  // Each class from the point's map where it says one ("" = none), else from the unit.
  const dissect::SensorClass* by_unit =
      options_.classes != nullptr ? options_.classes->for_unit(state.unit) : nullptr;
  std::string_view device_class;
  std::string_view state_class;
  if (by_unit != nullptr) {
    device_class = by_unit->device_class;
    state_class = by_unit->state_class;
  }
  if (const dissect::Point* def = sample.definition; def != nullptr) {
    if (def->device_class) device_class = *def->device_class;
    if (def->state_class) state_class = *def->state_class;
  }
  if (!device_class.empty()) json.field("device_class", device_class);
  if (!state_class.empty()) json.field("state_class", state_class);
  json.field("availability_topic", std::string_view(fmt::format("{}/{}/status", base_, slave)));
  json.key("device");
  json.begin_object();
  json.key("identifiers");
  json.begin_array();
  json.value(std::string_view(device_id));
  json.end_array();
  json.field("name", std::string_view(fmt::format("{} (slave {} on {})",
                                                  map != nullptr ? map->name : "Modbus device",
                                                  slave, options_.bus)));
  if (map != nullptr) {
    json.field("model", std::string_view(map->model));
    if (!map->vendor.empty()) json.field("manufacturer", std::string_view(map->vendor));
  }
  json.end_object();
  json.end_object();
  publish_({fmt::format("{}/sensor/{}/{}/config", options_.discovery_prefix, device_id, object_id),
            text_of(payload), true});
}

void MqttFeed::send_health(Nanos now) {
  last_health_ = now;
  fmt::memory_buffer payload;
  fmt::memory_buffer scratch;
  JsonWriter json(payload);
  json.begin_object();
  json.key("time");
  time_value(json, scratch, now);
  json.field("frames", frames_);
  json.field("noise", noise_);
  json.field("crc_errors", crc_errors_);
  json.field("timeouts", timeouts_);
  json.field("mqtt_dropped", options_.dropped ? options_.dropped() : std::uint64_t{0});
  json.end_object();
  publish_({base_ + "/health", text_of(payload), false});
}

}  // namespace rtu
