// rtuscope live PORT [PORT_B]: decodes a serial line as it happens (and records it with -w).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/command.hpp"
#include "app/device_options.hpp"
#include "app/line_options.hpp"
#include "app/live_session.hpp"
#include "app/monitoring_options.hpp"
#include "app/mqtt_options.hpp"
#include "core/input_error.hpp"
#include "dissect/map_loader.hpp"
#include "pipeline/line_warnings.hpp"
#include "pipeline/live_capture.hpp"
#include "pipeline/pcapng_recorder.hpp"
#include "report/record_formats.hpp"
#include "report/report_formats.hpp"

namespace rtu::app {
namespace {

struct LiveArgs {
  std::vector<std::string> ports;
  LineOptions line;
  DeviceOptions devices;
  std::string format = "text";
  std::string output = "-";
  double duration_s = 0.0;
  std::string write_path;
  std::string rotate;
  std::size_t keep = 0;
  std::string report;
  std::string report_format;
  MqttOptions mqtt;
  MonitoringOptions monitoring;
};

void print_summary(const LiveSummary& s) {
  fmt::print(stderr,
             "rtuscope: {:.1f} s, {} bytes in {} reads: {} frames ({} with CRC errors, {} with "
             "issues), {} transactions, {} timeouts, {} noise records, {} bytes with line "
             "errors, {} disconnects, {} idle wake-ups\n",
             to_seconds(s.duration), s.bytes, s.chunks, s.frames, s.crc_errors,
             s.frames_with_issues, s.transactions, s.timeouts, s.noise_records, s.line_error_bytes,
             s.disconnects, s.idle_wakeups);
  if (s.late_reads != 0) {
    fmt::print(stderr,
               "rtuscope: {} reads came later than the timing resolution allows (the host "
               "was busy or short of CPU, or the bytes waited in the port before it was "
               "opened): the silences next to them were not judged\n",
               s.late_reads);
  }
  if (s.timing_resolution > s.declared_resolution) {
    fmt::print(stderr,
               "rtuscope: the reads came in batches: gaps below {:.1f} ms were not observable "
               "(the port promised {:.1f} ms)\n",
               to_millis(s.timing_resolution), to_millis(s.declared_resolution));
  }
}

// A bus file's [live] section fills what the command line left out: `rtuscope live --bus
// FILE` alone starts a configured bus (one service instance per file).
void apply_bus_file_live(LiveArgs& args) {
  if (args.devices.bus_file.empty()) return;
  const dissect::LiveConfig live = dissect::load_bus_file(args.devices.bus_file).live;
  const auto fill = [](std::string& option, const std::string& from_file) {
    if (option.empty()) option = from_file;
  };
  if (args.ports.empty()) args.ports = live.ports;
  fill(args.write_path, live.write);
  fill(args.rotate, live.rotate);
  if (args.keep == 0 && live.keep) args.keep = *live.keep;
  fill(args.report, live.report);
  fill(args.monitoring.metrics, live.metrics);
  fill(args.monitoring.bus_name, live.bus_name);
  fill(args.monitoring.events, live.events);
  fill(args.monitoring.summary_every, live.summary_every);
}

void run_live(LiveArgs& args, int& exit_code) {
  apply_bus_file_live(args);
  if (args.ports.empty()) {
    throw InputError(
        "live: no port: give PORT (e.g. /dev/ttyUSB0), or --bus FILE with "
        "[live] port = \"...\"");
  }
  // Line settings: the command line, else the --bus file, else Modbus's 9600 8E1.
  ReplayOptions line = args.line.to_replay_options();
  const auto devices = args.devices.build_with_maps(line);
  LiveSessionSetup session;
  LiveOptions& options = session.capture;
  options.ports = args.ports;
  options.line.baud = line.overrides.baud.value_or(options.line.baud);
  options.line.parity = line.overrides.parity.value_or(options.line.parity);
  options.line.stop_bits = line.overrides.stop_bits.value_or(options.line.stop_bits);
  options.response_timeout = line.response_timeout;
  options.duration = static_cast<Nanos>(args.duration_s * 1e9);
  // A port says nothing about its line: settings no option gave are Modbus's defaults, and
  // the user is told so (on stderr and in the header), as a replay would.
  const auto warning = line.overrides.baud
                           ? std::nullopt
                           : assumed_settings_warning(options.line, false, line.overrides);
  if (warning) {
    fmt::print(stderr, "rtuscope: warning: {}\n", *warning);
    options.warnings.push_back(*warning);
  }

  if (!args.write_path.empty()) {
    session.record_path = args.write_path;
    if (!args.rotate.empty()) session.rotation = parse_rotation(args.rotate);
    session.rotation.keep = args.keep;
  } else if (!args.rotate.empty() || args.keep != 0) {
    throw InputError("--rotate and --keep need -w FILE.pcapng");
  }
  session.format = args.format;
  session.output = args.output;
  session.report_path = args.report;
  session.report_format = args.report_format;
  args.monitoring.apply(session);

  LiveSessionHooks hooks;
  hooks.on_listening = [&options](const LiveCapture& capture) {
    fmt::print(stderr, "rtuscope: listening on {} at {} (Ctrl-C to stop)\n", capture.info().source,
               options.line.describe());
  };
  hooks.on_stopped = [](const LiveSummary& summary, const PcapngRecorder* recorder) {
    print_summary(summary);
    if (recorder) {
      fmt::print(stderr, "rtuscope: {} records written to {}\n", recorder->records(),
                 fmt::join(recorder->files(), ", "));
      if (!recorder->failure().empty()) {
        fmt::print(stderr,
                   "rtuscope: the recording stopped early; {} reads after it were decoded "
                   "but not recorded\n",
                   recorder->unrecorded_reads());
      }
    }
  };
  std::unique_ptr<MqttPublishing> mqtt;
  if (args.mqtt.enabled()) {
    mqtt = std::make_unique<MqttPublishing>(
        args.mqtt, std::filesystem::path(args.ports.front()).filename().string(), "rtuscope");
    mqtt->attach(session, hooks);
  }
  run_live_session(session, *devices, hooks);
  if (mqtt) mqtt->finish();
  exit_code = 0;
}

void setup_live(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<LiveArgs>();
  auto* cmd = app.add_subcommand("live",
                                 "Decode a serial line live (one port, or two for the "
                                 "two directions of a link)");
  cmd->add_option("ports", args->ports,
                  "Serial port(s), e.g. /dev/ttyUSB0 (default: the --bus file's [live] port)")
      ->expected(0, 2);
  args->line.add_to(*cmd, false);
  args->devices.add_to(*cmd);
  cmd->add_option("--format", args->format, "Output format")
      ->check(CLI::IsMember(format_names(record_formats())));
  cmd->add_option("-o,--output", args->output, "Output file (default: standard output)");
  cmd->add_option("--duration", args->duration_s,
                  "Stop after this many seconds (default: run "
                  "until Ctrl-C)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("-w,--write", args->write_path,
                  "Record every read, exactly as read, to this pcapng file (LINKTYPE 250)");
  cmd->add_option("--rotate", args->rotate,
                  "Start a new file at this size or age (e.g. 100MB, 1h); files get -0001, ..., "
                  "going on after the highest number already there");
  cmd->add_option("--keep", args->keep,
                  "With --rotate: keep only the newest N files (the set's older ones count too)");
  cmd->add_option("--report", args->report,
                  "When the run stops, write its traffic report to this file (as `rtuscope "
                  "report` would) and list the main findings");
  cmd->add_option("--report-format", args->report_format,
                  "Report format (default: from the file name: .html, .json, else text)")
      ->check(CLI::IsMember(format_names(report_formats())));
  args->mqtt.add_to(*cmd);
  args->monitoring.add_to(*cmd);
  cmd->callback([args, &exit_code] { run_live(*args, exit_code); });
}

RTUSCOPE_REGISTER_COMMAND(setup_live);

}  // namespace
}  // namespace rtu::app
