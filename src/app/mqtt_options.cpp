#include "app/mqtt_options.hpp"

#include <fmt/format.h>
#include <unistd.h>

namespace rtu::app {

void MqttOptions::add_to(CLI::App& command) {
  command.add_option("--mqtt", url,
                     "Publish the decoded device points, slave status, findings and bus health "
                     "to this MQTT broker: mqtt://HOST[:PORT] or mqtts://HOST[:PORT] (TLS)");
  command
      .add_option("--mqtt-credentials", credentials_file,
                  "File with the MQTT user name (line 1) and password (line 2)")
      ->check(CLI::ExistingFile);
  command.add_flag("--mqtt-discovery", discovery,
                   "Also send Home Assistant discovery configs (retained, prefix homeassistant)");
  command.add_option("--mqtt-bus", bus,
                     "The bus's name in the topics rtuscope/<bus>/... (default: the port's name)");
  command
      .add_option("--mqtt-queue", queue_limit,
                  "Messages kept while the broker is away; beyond, the oldest are dropped "
                  "(default 10000)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{10000000}));
}

MqttPublishing::MqttPublishing(const MqttOptions& options, const std::string& default_bus,
                               std::string prefix)
    : prefix_(std::move(prefix)) {
  const std::string bus = options.bus.empty() ? default_bus : options.bus;
  if (options.discovery) {
    const std::string path = dissect::SensorClasses::bundled_path();
    if (!path.empty()) classes_ = dissect::SensorClasses::load_file(path);
  }
  MqttClientOptions client;
  client.url = parse_mqtt_url(options.url);
  if (!options.credentials_file.empty()) {
    client.credentials = read_mqtt_credentials(options.credentials_file);
  }
  client.client_id = fmt::format("rtuscope-{}-{}", mqtt_id(bus), ::getpid());
  client.status_topic = mqtt_base_topic(bus) + "/status";
  client.queue_limit = options.queue_limit;
  client.on_event = [this](const std::string& event) {
    fmt::print(stderr, "{}: {}\n", prefix_, event);
  };
  client_ = std::make_unique<MqttClient>(std::move(client));

  MqttFeedOptions feed;
  feed.bus = bus;
  feed.discovery = options.discovery;
  feed.classes = &classes_;
  feed.dropped = [this] { return client_->dropped(); };
  feed_ = std::make_unique<MqttFeed>(
      std::move(feed), [this](MqttMessage&& message) { client_->publish(std::move(message)); });
}

MqttPublishing::~MqttPublishing() = default;

void MqttPublishing::attach(LiveSessionSetup& setup, LiveSessionHooks& hooks) {
  setup.extra_sinks.push_back(feed_.get());
  auto before = std::move(hooks.periodic);
  hooks.periodic = [this, before = std::move(before)] {
    if (before) before();
    client_->pump();
  };
}

void MqttPublishing::finish() {
  if (finished_) return;
  finished_ = true;
  client_->close(std::chrono::seconds(3));
  fmt::print(stderr, "{}: mqtt: {} messages published, {} dropped\n", prefix_, client_->published(),
             client_->dropped());
}

}  // namespace rtu::app
