// rtuscope demo: no hardware needed. Starts a virtual RS-485 bus on pseudo-terminals, plays
// simulated traffic of the project's four devices on it from two endpoints (the master's
// requests from one, the slaves' answers from another, at their recorded pace), and sniffs
// a third endpoint live through the same serial path as `rtuscope live`; then prints a
// summary.
#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "app/command.hpp"
#include "app/device_options.hpp"
#include "app/live_session.hpp"
#include "app/monitoring_options.hpp"
#include "app/mqtt_options.hpp"
#include "capture/capture_paths.hpp"
#include "core/input_error.hpp"
#include "pipeline/burst_collector.hpp"
#include "pipeline/replay.hpp"
#include "pipeline/traffic_player.hpp"
#include "report/record_formats.hpp"
#include "serial/virtual_bus.hpp"

namespace rtu::app {
namespace {

struct DemoArgs {
  std::string traffic;
  DeviceOptions devices;
  std::string format = "text";
  std::string write_path;
  std::string report;
  unsigned repeat = 1;
  MqttOptions mqtt;
  MonitoringOptions monitoring;
};

// The bundled traffic: the simulator's master polling the four documented devices
// (slaves 1-4), with a few faults, and the bus file that says which slave is which.
std::filesystem::path default_traffic() {
  const std::filesystem::path sources =
      std::filesystem::path(RTUSCOPE_DISSECTORS_DIR).parent_path();
  return sources / "captures" / "demo_four_devices.hex";
}

void print_summary(const LiveSummary& s, const VirtualBus& bus) {
  std::size_t written = 0;
  for (const auto& b : bus.log()) written += b.bytes.size();
  fmt::print(stderr,
             "rtuscope demo: {:.1f} s; the bus carried {} bytes, rtuscope read {} of them in {} "
             "reads: {} frames ({} with issues), {} transactions, {} timeouts, {} noise "
             "records\n",
             to_seconds(s.duration), written, s.bytes, s.chunks, s.frames, s.frames_with_issues,
             s.transactions, s.timeouts, s.noise_records);
}

void run_demo(DemoArgs& args, int& exit_code) {
  std::string traffic = args.traffic;
  if (traffic.empty()) {
    traffic = default_traffic().string();
    if (args.devices.devices.empty() && args.devices.bus_file.empty()) {
      args.devices.bus_file = default_traffic().replace_extension(".bus.toml").string();
    }
  }
  ReplayOptions replay;
  const auto devices = args.devices.build_with_maps(replay);
  BurstCollector collector;
  const auto traffic_file = capture_inputs({traffic});
  const CaptureInfo traffic_info = replay_capture(traffic_file, replay, collector);
  if (collector.bursts.empty()) {
    throw InputError(fmt::format("{}: no traffic to play", traffic_file.front().name));
  }

  VirtualBusOptions bus_options;
  bus_options.endpoints = 3;
  bus_options.line = traffic_info.line;
  VirtualBus bus(bus_options);
  fmt::print(stderr,
             "rtuscope demo: virtual RS-485 bus {} on {}, {}, {}; the master on the first, the "
             "four slaves on the second, rtuscope live on the third\n",
             traffic_info.line.describe(), bus.paths()[0], bus.paths()[1], bus.paths()[2]);
  bus.start();

  LiveSessionSetup session;
  session.capture.ports = {bus.paths()[2]};
  session.capture.line = traffic_info.line;
  session.capture.response_timeout = replay.response_timeout;
  session.format = args.format;
  session.record_path = args.write_path;
  session.report_path = args.report;
  session.always_report = true;  // the demo shows its findings even without --report
  session.prefix = "rtuscope demo";
  args.monitoring.apply(session);

  // The traffic starts once rtuscope listens, and the run ends once it is over; a Ctrl-C
  // stops the traffic, and the run then ends the same way. With --metrics the run goes on
  // after the traffic until Ctrl-C (or SIGTERM), so the final counts can still be scraped.
  const bool serve_until_signal = !args.monitoring.metrics.empty();
  bool signalled = false;
  bool said_traffic_over = false;
  std::optional<TrafficPlayer> player;
  LiveSessionHooks hooks;
  hooks.on_listening = [&](const LiveCapture&) {
    player.emplace(std::move(collector.bursts), args.repeat, bus.paths()[0], bus.paths()[1],
                   traffic_info.line.char_time());
  };
  hooks.finished = [&] {
    if (!player || !player->done()) return false;
    if (!serve_until_signal || signalled) return true;
    if (!said_traffic_over) {
      said_traffic_over = true;
      fmt::print(stderr, "rtuscope demo: traffic over; still serving metrics (Ctrl-C to stop)\n");
    }
    return false;
  };
  hooks.on_signal = [&] {
    signalled = true;
    if (player) player->stop();
  };
  hooks.on_stopped = [&](const LiveSummary& summary, const PcapngRecorder*) {
    player.reset();
    bus.stop();  // every byte played is in its log now
    print_summary(summary, bus);
  };
  std::unique_ptr<MqttPublishing> mqtt;
  if (args.mqtt.enabled()) {
    mqtt = std::make_unique<MqttPublishing>(args.mqtt, "demo", "rtuscope demo");
    mqtt->attach(session, hooks);
  }
  run_live_session(session, *devices, hooks);
  if (mqtt) mqtt->finish();
  if (!args.write_path.empty()) {
    fmt::print(stderr, "rtuscope demo: recorded to {} (replay: rtuscope decode {})\n",
               args.write_path, args.write_path);
  }
  exit_code = 0;
}

void setup_demo(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<DemoArgs>();
  auto* cmd = app.add_subcommand(
      "demo", "Sniff a virtual RS-485 bus carrying simulated traffic, live (no hardware needed)");
  cmd->add_option("--traffic", args->traffic,
                  "Capture whose frames are played on the bus; - reads standard input "
                  "(default: the bundled four-device sample)");
  args->devices.add_to(*cmd);
  cmd->add_option("--format", args->format, "Output format")
      ->check(CLI::IsMember(format_names(record_formats())));
  cmd->add_option("-w,--write", args->write_path, "Also record the demo to this pcapng file");
  cmd->add_option("--report", args->report,
                  "Also write the run's traffic report to this file (.html, .json, else text)");
  cmd->add_option("--repeat", args->repeat, "Play the traffic this many times (default 1)")
      ->check(CLI::Range(1U, 1000U));
  args->mqtt.add_to(*cmd);
  args->monitoring.bus_name = "demo";
  args->monitoring.add_to(*cmd);
  cmd->callback([args, &exit_code] { run_demo(*args, exit_code); });
}

RTUSCOPE_REGISTER_COMMAND(setup_demo);

}  // namespace
}  // namespace rtu::app
