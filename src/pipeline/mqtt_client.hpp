#pragma once
// Publishes MqttMessages to a broker with libmosquitto, without ever holding up the capture.
//
//  * A starter thread makes the first connection (name lookup included), retrying with a
//    back-off (1 s doubling to 30 s) while the broker cannot be reached; then libmosquitto
//    runs its network loop on a thread of its own (mosquitto_loop_start): it writes, and
//    reconnects with the same back-off when the connection is lost. The capture
//    thread only puts messages into a bounded queue (publish) and, from its timers, hands
//    them to libmosquitto while connected (pump); neither waits for the network.
//  * The queue holds at most `queue_limit` messages: when full, the oldest is dropped and
//    counted. Only a few messages at a time are handed to libmosquitto, so a broker that is
//    away fills the queue, not memory.
//  * Retained messages (statuses, discovery configs) are also remembered by topic and sent
//    again after every reconnect, so a broker restarted without persistence gets them back.
//  * Last will: <base>/status "offline" (retained); "online" once connected; close() sends
//    "offline" itself, since a clean disconnect sends no will.
//  * Events (connected, connection lost, messages dropped) are collected from the network
//    thread and handed to `on_event` by pump(), on the capture thread.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "report/mqtt_feed.hpp"

struct mosquitto;

namespace rtu {

struct MqttUrl {
  bool tls = false;
  std::string host;
  int port = 1883;
};

// "mqtt://host[:port]" (1883) or "mqtts://host[:port]" (8883, TLS with the system's CAs).
// Throws InputError starting "--mqtt:" for anything else.
[[nodiscard]] MqttUrl parse_mqtt_url(const std::string& url);

struct MqttCredentials {
  std::string user;
  std::string password;
};

// A file of two lines, user then password (so neither shows in `ps`). Throws InputError
// "file: ..." when it cannot be read or has no user.
[[nodiscard]] MqttCredentials read_mqtt_credentials(const std::string& path);

struct MqttClientOptions {
  MqttUrl url;
  std::optional<MqttCredentials> credentials;
  std::string client_id;
  std::string status_topic;  // rtuscope's own online/offline, and its last will
  std::size_t queue_limit = 10000;
  std::function<void(const std::string& event)> on_event;
};

class MqttClient {
 public:
  // Starts connecting in the background. Throws InputError for options libmosquitto
  // refuses (e.g. TLS unavailable); a broker that is down is not an error: it is tried
  // again until it answers.
  explicit MqttClient(MqttClientOptions options);
  ~MqttClient();
  MqttClient(const MqttClient&) = delete;
  MqttClient& operator=(const MqttClient&) = delete;

  void publish(MqttMessage&& message);
  // Hands queued messages to libmosquitto while connected and reports events. Call often
  // (every few ms) from the thread that publishes.
  void pump();
  // Sends "offline", waits up to `grace` for the queue to drain, then disconnects.
  void close(std::chrono::milliseconds grace);

  [[nodiscard]] std::uint64_t dropped() const { return dropped_.load(); }
  [[nodiscard]] std::uint64_t published() const { return published_.load(); }

 private:
  void start_connecting();  // the starter thread
  static void on_connect(mosquitto* mosq, void* self, int rc);
  static void on_disconnect(mosquitto* mosq, void* self, int rc);
  static void on_publish(mosquitto* mosq, void* self, int mid);

  MqttClientOptions options_;
  mosquitto* mosq_ = nullptr;
  bool closed_ = false;
  std::thread starter_;

  std::mutex mutex_;  // guards everything below, shared with the other threads
  std::condition_variable stop_starting_;
  bool stopping_ = false;
  bool loop_running_ = false;
  std::deque<MqttMessage> queue_;
  std::map<std::string, MqttMessage> retained_;  // by topic
  std::vector<std::string> events_;
  bool connected_ = false;
  bool resend_retained_ = false;
  std::size_t in_flight_ = 0;  // handed to libmosquitto, not yet written
  std::uint64_t dropped_reported_ = 0;

  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> published_{0};
};

}  // namespace rtu
