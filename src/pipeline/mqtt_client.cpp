#include "pipeline/mqtt_client.hpp"

#include <fmt/format.h>
#include <mosquitto.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <thread>

#include "core/input_error.hpp"
#include "core/thread_name.hpp"

namespace rtu {
namespace {

// Messages handed to libmosquitto and not yet written: enough to keep the socket busy,
// few enough that a broker going away strands little inside the library.
constexpr std::size_t kMaxInFlight = 64;
constexpr int kKeepaliveSeconds = 30;

void init_library_once() {
  static const int rc = mosquitto_lib_init();
  (void)rc;
}

}  // namespace

MqttUrl parse_mqtt_url(const std::string& url) {
  MqttUrl parsed;
  std::string rest;
  if (url.starts_with("mqtt://")) {
    rest = url.substr(7);
  } else if (url.starts_with("mqtts://")) {
    rest = url.substr(8);
    parsed.tls = true;
    parsed.port = 8883;
  } else {
    throw InputError(
        fmt::format("--mqtt: expected mqtt://HOST[:PORT] or mqtts://HOST[:PORT], found '{}'", url));
  }
  if (!rest.empty() && rest.back() == '/') rest.pop_back();
  const std::size_t colon = rest.rfind(':');
  if (colon != std::string::npos && rest.find(']') == std::string::npos) {
    const std::string port = rest.substr(colon + 1);
    int value = 0;
    bool ok = !port.empty() && port.size() <= 5;
    for (const char c : port) {
      if (c < '0' || c > '9') ok = false;
      value = value * 10 + (c - '0');
    }
    if (!ok || value < 1 || value > 65535) {
      throw InputError(fmt::format("--mqtt: '{}': the port must be 1..65535", url));
    }
    parsed.port = value;
    rest.resize(colon);
  }
  if (rest.empty() || rest.find_first_of("/@ ") != std::string::npos) {
    throw InputError(
        fmt::format("--mqtt: '{}': expected a host name or address (a user and password go in "
                    "--mqtt-credentials FILE)",
                    url));
  }
  parsed.host = rest;
  return parsed;
}

MqttCredentials read_mqtt_credentials(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot read the MQTT credentials", path));
  MqttCredentials credentials;
  std::getline(in, credentials.user);
  std::getline(in, credentials.password);
  for (std::string* line : {&credentials.user, &credentials.password}) {
    while (!line->empty() && (line->back() == '\r' || line->back() == '\n')) line->pop_back();
  }
  if (credentials.user.empty()) {
    throw InputError(fmt::format("{}:1: expected the MQTT user name (line 2: the password)", path));
  }
  return credentials;
}

MqttClient::MqttClient(MqttClientOptions options) : options_(std::move(options)) {
  init_library_once();
  mosq_ = mosquitto_new(options_.client_id.c_str(), true, this);
  if (mosq_ == nullptr) throw InputError("--mqtt: cannot create an MQTT client");
  const auto check = [this](int rc, std::string_view what) {
    if (rc != MOSQ_ERR_SUCCESS) {
      mosquitto_destroy(mosq_);  // the destructor does not run for a throwing constructor
      throw InputError(fmt::format("--mqtt: {}: {}", what, mosquitto_strerror(rc)));
    }
  };
  constexpr std::string_view kOffline = "offline";
  check(mosquitto_will_set(mosq_, options_.status_topic.c_str(), static_cast<int>(kOffline.size()),
                           kOffline.data(), 1, true),
        "last will");
  if (options_.credentials) {
    check(mosquitto_username_pw_set(mosq_, options_.credentials->user.c_str(),
                                    options_.credentials->password.c_str()),
          "credentials");
  }
  if (options_.url.tls) {
    check(mosquitto_tls_set(mosq_, nullptr, "/etc/ssl/certs", nullptr, nullptr, nullptr), "TLS");
  }
  check(mosquitto_reconnect_delay_set(mosq_, 1, 30, true), "reconnect delay");
  mosquitto_connect_callback_set(mosq_, &MqttClient::on_connect);
  mosquitto_disconnect_callback_set(mosq_, &MqttClient::on_disconnect);
  mosquitto_publish_callback_set(mosq_, &MqttClient::on_publish);
  retained_[options_.status_topic] = {options_.status_topic, "online", true};

  starter_ = std::thread([this] {
    name_this_thread("rtu-mqtt-start");
    start_connecting();
  });
}

void MqttClient::start_connecting() {
  std::chrono::seconds delay(1);
  for (;;) {
    const int rc = mosquitto_connect_async(mosq_, options_.url.host.c_str(), options_.url.port,
                                           kKeepaliveSeconds);
    const std::string reason = rc == MOSQ_ERR_ERRNO ? std::strerror(errno) : mosquitto_strerror(rc);
    std::unique_lock lock(mutex_);
    if (stopping_) return;
    if (rc == MOSQ_ERR_SUCCESS) {
      // From here on libmosquitto's loop reconnects by itself.
      const int loop = mosquitto_loop_start(mosq_);
      loop_running_ = loop == MOSQ_ERR_SUCCESS;
      if (!loop_running_) {
        events_.push_back(
            fmt::format("mqtt: cannot start the network thread: {}", mosquitto_strerror(loop)));
      }
      return;
    }
    if (delay == std::chrono::seconds(1)) {
      events_.push_back(fmt::format("mqtt: cannot reach {}:{} ({}); retrying with back-off",
                                    options_.url.host, options_.url.port, reason));
    }
    if (stop_starting_.wait_for(lock, delay, [this] { return stopping_; })) return;
    delay = std::min(delay * 2, std::chrono::seconds(30));
  }
}

MqttClient::~MqttClient() {
  if (!closed_) close(std::chrono::milliseconds(0));
  mosquitto_destroy(mosq_);
}

void MqttClient::publish(MqttMessage&& message) {
  const std::lock_guard lock(mutex_);
  if (message.retain) retained_[message.topic] = message;
  if (queue_.size() >= options_.queue_limit) {
    queue_.pop_front();
    if (dropped_.fetch_add(1) == 0) {
      events_.push_back(fmt::format(
          "mqtt: queue full ({} messages): dropping the oldest while the broker is away",
          options_.queue_limit));
    }
  }
  queue_.push_back(std::move(message));
}

void MqttClient::pump() {
  std::vector<MqttMessage> batch;
  std::vector<std::string> events;
  {
    const std::lock_guard lock(mutex_);
    events.swap(events_);
    if (connected_) {
      if (dropped_ > dropped_reported_) {
        events.push_back(
            fmt::format("mqtt: {} messages dropped so far (oldest first)", dropped_.load()));
        dropped_reported_ = dropped_;
      }
      if (resend_retained_) {
        for (const auto& [topic, message] : retained_) batch.push_back(message);
        resend_retained_ = false;
      }
      while (!queue_.empty() && in_flight_ + batch.size() < kMaxInFlight) {
        batch.push_back(std::move(queue_.front()));
        queue_.pop_front();
      }
      in_flight_ += batch.size();
    }
  }
  if (options_.on_event) {
    for (const auto& event : events) options_.on_event(event);
  }
  for (const auto& message : batch) {
    // QoS 1 for the retained state (statuses, configs), QoS 0 for the flow of values.
    const int rc = mosquitto_publish(
        mosq_, nullptr, message.topic.c_str(), static_cast<int>(message.payload.size()),
        message.payload.data(), message.retain ? 1 : 0, message.retain);
    if (rc != MOSQ_ERR_SUCCESS) {
      // The connection went in between: the message is lost like a dropped one.
      const std::lock_guard lock(mutex_);
      if (in_flight_ > 0) --in_flight_;
      dropped_.fetch_add(1);
    }
  }
}

void MqttClient::close(std::chrono::milliseconds grace) {
  if (closed_) return;
  closed_ = true;
  publish({options_.status_topic, "offline", true});
  const auto deadline = std::chrono::steady_clock::now() + grace;
  for (;;) {
    pump();
    {
      const std::lock_guard lock(mutex_);
      if (!connected_ || (queue_.empty() && in_flight_ == 0)) break;
    }
    if (std::chrono::steady_clock::now() >= deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  pump();  // the last events
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  stop_starting_.notify_all();
  if (starter_.joinable()) starter_.join();
  mosquitto_disconnect(mosq_);
  if (loop_running_) mosquitto_loop_stop(mosq_, false);
  loop_running_ = false;
}

void MqttClient::on_connect(mosquitto* /*mosq*/, void* self, int rc) {
  auto& client = *static_cast<MqttClient*>(self);
  const std::lock_guard lock(client.mutex_);
  if (rc != 0) {
    client.events_.push_back(fmt::format("mqtt: {}:{} refused the connection: {}",
                                         client.options_.url.host, client.options_.url.port,
                                         mosquitto_connack_string(rc)));
    return;
  }
  client.connected_ = true;
  client.resend_retained_ = true;
  client.in_flight_ = 0;
  client.events_.push_back(
      fmt::format("mqtt: connected to {}:{}", client.options_.url.host, client.options_.url.port));
}

void MqttClient::on_disconnect(mosquitto* /*mosq*/, void* self, int rc) {
  auto& client = *static_cast<MqttClient*>(self);
  const std::lock_guard lock(client.mutex_);
  const bool was_connected = client.connected_;
  client.connected_ = false;
  client.in_flight_ = 0;
  if (rc != 0 && was_connected) {
    client.events_.push_back(fmt::format(
        "mqtt: connection to {}:{} lost ({}); reconnecting with back-off, queueing up to {} "
        "messages",
        client.options_.url.host, client.options_.url.port, mosquitto_strerror(rc),
        client.options_.queue_limit));
  }
}

void MqttClient::on_publish(mosquitto* /*mosq*/, void* self, int /*mid*/) {
  auto& client = *static_cast<MqttClient*>(self);
  client.published_.fetch_add(1);
  const std::lock_guard lock(client.mutex_);
  if (client.in_flight_ > 0) --client.in_flight_;
}

}  // namespace rtu
