#pragma once
// What rtuscope tells an MQTT broker about a bus, decided from the decoded records alone (no
// network here: the messages go to a callback, see pipeline/mqtt_client.hpp). Only what was
// seen on the wire is published; nothing offers to write to a device.
//
// Topics, under rtuscope/<bus>/ (<bus> and point names reduced to [A-Za-z0-9_-]):
//   <slave>/<point>  {"value":229.8,"unit":"V","time":"2026-…Z","model":"yw2050"} when the
//                    value changes, at most once per `min_interval` per point (a change
//                    within it is sent when the interval is over, the latest value wins)
//   <slave>/status   "online" once it answers, "offline" after `offline_after` timeouts in a
//                    row (retained)
//   findings         {"slave":1,"issue":"crc","summary":"…","time":"…"} the first time
//                    each issue arises on each slave
//   health           {"time":…,"frames":…,"noise":…,"crc_errors":…,"timeouts":…,
//                    "mqtt_dropped":…} every `health_period`
//   status           "online"/"offline" for rtuscope itself (set by the client, as last will)
// With discovery, before a point's first value: a retained Home Assistant sensor config at
// <prefix>/sensor/rtuscope_<bus>_<slave>/<point>/config, with the unit, and device_class and
// state_class: each as the point's device map states it, else the unit's from SensorClasses;
// one device per slave.
//
// Times are the records' (capture time), so a replay would publish the same.
#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <utility>

#include "core/time.hpp"
#include "dissect/point_value.hpp"
#include "dissect/sensor_classes.hpp"
#include "framing/record.hpp"

namespace rtu {

struct MqttMessage {
  std::string topic;
  std::string payload;
  bool retain = false;
};

struct MqttFeedOptions {
  std::string bus = "bus";  // reduced to [A-Za-z0-9_-] for topics
  bool discovery = false;
  std::string discovery_prefix = "homeassistant";
  const dissect::SensorClasses* classes = nullptr;  // null: no classes in configs
  Nanos min_interval = kNanosPerSecond;
  unsigned offline_after = 3;  // timeouts in a row
  Nanos health_period = 10 * kNanosPerSecond;
  std::function<std::uint64_t()> dropped;  // messages the client dropped (for health)
};

// "Ua L1" → "Ua_L1": what topics and Home Assistant ids may hold.
[[nodiscard]] std::string mqtt_id(std::string_view text);
// rtuscope/<bus>
[[nodiscard]] std::string mqtt_base_topic(std::string_view bus);

class MqttFeed final : public RecordSink {
 public:
  using Publish = std::function<void(MqttMessage&& message)>;
  MqttFeed(MqttFeedOptions options, Publish publish);

  void on_record(Record& record) override;
  // Sends the changes still held back by min_interval and a last health message.
  void on_finish() override;

 private:
  struct PointState {
    std::string topic;
    std::string unit;
    std::string model;
    bool sent_once = false;
    double sent = 0.0;
    Nanos sent_at = 0;
    bool pending = false;
    double value = 0.0;
    Nanos value_at = 0;
  };
  struct SlaveState {
    bool online = false;
    bool known = false;  // a status was published
    unsigned timeouts_in_a_row = 0;
  };

  void slave_status(std::uint8_t slave, bool online);
  void point_value(const Record& record, const dissect::PointValue& sample);
  void send_value(PointState& point);
  void send_due(Nanos now);
  void send_discovery(std::uint8_t slave, const dissect::PointValue& sample,
                      const PointState& state, const Record& record);
  void send_health(Nanos now);

  MqttFeedOptions options_;
  Publish publish_;
  std::string base_;
  std::map<std::string, PointState, std::less<>> points_;  // by topic
  std::map<std::uint8_t, SlaveState> slaves_;
  std::set<std::pair<std::uint8_t, IssueId>> findings_seen_;
  Nanos last_due_check_ = 0;
  Nanos last_health_ = kUnknownTime;
  Nanos last_t_ = 0;
  std::uint64_t frames_ = 0;
  std::uint64_t noise_ = 0;
  std::uint64_t crc_errors_ = 0;
  std::uint64_t timeouts_ = 0;
};

}  // namespace rtu
