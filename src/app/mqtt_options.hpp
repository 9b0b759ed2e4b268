#pragma once
// The MQTT options of `live` and `demo` (--mqtt URL, --mqtt-credentials FILE,
// --mqtt-discovery, --mqtt-bus NAME, --mqtt-queue N) and the publishing they switch on: a
// feed of the decoded records (report/mqtt_feed.hpp) into a client (pipeline/mqtt_client.hpp),
// wired into a live session.
#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "app/live_session.hpp"
#include "dissect/sensor_classes.hpp"
#include "pipeline/mqtt_client.hpp"
#include "report/mqtt_feed.hpp"

namespace rtu::app {

struct MqttOptions {
  std::string url;  // "" = no MQTT
  std::string credentials_file;
  bool discovery = false;
  std::string bus;  // "" = the command's default
  std::size_t queue_limit = 10000;

  void add_to(CLI::App& command);
  [[nodiscard]] bool enabled() const { return !url.empty(); }
};

class MqttPublishing {
 public:
  // Starts connecting. Throws InputError for a bad URL, credentials file or sensor classes
  // file. Messages on stderr start with `prefix`.
  MqttPublishing(const MqttOptions& options, const std::string& default_bus, std::string prefix);
  ~MqttPublishing();
  MqttPublishing(const MqttPublishing&) = delete;
  MqttPublishing& operator=(const MqttPublishing&) = delete;

  // Adds the feed to the session's sinks and the client's pump to its periodic hook.
  void attach(LiveSessionSetup& setup, LiveSessionHooks& hooks);
  // After the session: sends what is queued (up to 3 s), "offline", disconnects, and says
  // how many messages went out and how many were dropped.
  void finish();

 private:
  std::string prefix_;
  dissect::SensorClasses classes_;
  std::unique_ptr<MqttClient> client_;
  std::unique_ptr<MqttFeed> feed_;
  bool finished_ = false;
};

}  // namespace rtu::app
