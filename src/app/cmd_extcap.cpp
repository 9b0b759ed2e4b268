// rtuscope extcap: Wireshark's capture interface (extcap). Wireshark runs it to list the
// serial ports, their link types and options, and to capture: the live decode of a port
// streamed as pcapng into the FIFO Wireshark reads, one block per frame as soon as it is
// decided. Wireshark calls its extcaps by file name with extcap arguments only, so
// tools/install-extcap.sh installs a two-line script that runs `rtuscope extcap "$@"`.
#include <fmt/format.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/command.hpp"
#include "app/device_options.hpp"
#include "app/live_session.hpp"
#include "capture/pipe_output.hpp"
#include "core/input_error.hpp"
#include "pipeline/pcapng_recorder.hpp"
#include "report/extcap_text.hpp"
#include "report/pcap_export.hpp"
#include "serial/line_settings.hpp"
#include "serial/port_discovery.hpp"

namespace rtu::app {
namespace {

struct ExtcapArgs {
  bool list_interfaces = false;
  std::string wireshark_version;  // --extcap-version=4.0; informational
  std::string interface;
  bool dlts = false;
  bool config = false;
  bool capture = false;
  std::string fifo;
  // Accepted so that Wireshark's calls parse; rtuscope has no capture filter and no
  // toolbar controls, so they change nothing.
  std::string capture_filter;
  std::string control_in;
  std::string control_out;
  std::string reload_option;
  bool debug = false;
  std::string debug_file;
  // The interface's options (report/extcap_text.hpp lists them for Wireshark).
  std::optional<std::uint32_t> baud;
  std::string parity{extcap::kAuto};
  std::string stop{extcap::kAuto};
  std::optional<double> timeout_ms;
  DeviceOptions devices;
  std::string link_type{extcap::kLinkFrames};
};

// The ports this machine has, then those in RTUSCOPE_EXTCAP_PORTS (colon-separated; e.g. a
// virtual bus's pseudo-terminals), each once, as absolute paths.
std::vector<std::string> listed_ports() {
  std::vector<std::string> ports = find_serial_ports();
  if (const char* extra = std::getenv("RTUSCOPE_EXTCAP_PORTS")) {
    for (const auto& path : split_port_list(extra)) {
      const std::string absolute = std::filesystem::absolute(path).lexically_normal().string();
      if (std::find(ports.begin(), ports.end(), absolute) == ports.end()) {
        ports.push_back(absolute);
      }
    }
  }
  return ports;
}

std::string port_of(const ExtcapArgs& args) {
  if (args.interface.empty()) throw InputError("extcap: --extcap-interface IFACE is needed");
  auto port = extcap::port_for_interface(args.interface);
  if (!port) {
    throw InputError(fmt::format(
        "extcap: --extcap-interface '{}' is not an rtuscope interface (expected {}/PATH)",
        args.interface, extcap::kInterfacePrefix));
  }
  return *port;
}

// The line options as `live` takes them: "auto" and empty mean "not given".
ReplayOptions line_options(const ExtcapArgs& args) {
  ReplayOptions options;
  options.overrides.baud = args.baud;
  if (args.parity != extcap::kAuto) {
    options.overrides.parity = parse_parity(args.parity);
    if (!options.overrides.parity) {
      throw InputError(fmt::format("extcap: --parity: expected E, N, O or {}, found '{}'",
                                   extcap::kAuto, args.parity));
    }
  }
  if (args.stop == "1" || args.stop == "2") {
    options.overrides.stop_bits = static_cast<std::uint8_t>(args.stop[0] - '0');
  } else if (args.stop != extcap::kAuto) {
    throw InputError(
        fmt::format("extcap: --stop: expected 1, 2 or {}, found '{}'", extcap::kAuto, args.stop));
  }
  if (args.timeout_ms) {
    options.response_timeout = static_cast<Nanos>(*args.timeout_ms * 1e6);
    options.response_timeout_set = true;
  }
  return options;
}

// In raw mode the frames are decoded (the capture needs its decisions) but not written.
class DiscardRecords final : public RecordSink {
 public:
  void on_record(Record& record) override { (void)record; }
};

// Returns the exit status: 0 when Wireshark stopped the capture, 2 when it could not run
// (the reason is on stderr, where Wireshark shows it).
int run_capture(const ExtcapArgs& args) {
  // Wireshark waits for the FIFO to be opened and hangs if the extcap fails before, so the
  // FIFO is opened first and every check comes after it.
  if (args.fifo.empty()) throw InputError("extcap: --capture needs --fifo PATH");
  std::signal(SIGPIPE, SIG_IGN);  // a closed reader shows as EPIPE (PipeOutput)
  auto pipe = std::make_unique<PipeOutput>(args.fifo);
  PipeOutput& reader = *pipe;
  // Whichever writes into the pipe; they outlive the error message below, so the reason is
  // on stderr before the FIFO closes and Wireshark looks for it.
  std::unique_ptr<PcapExportSink> frames;
  std::unique_ptr<PcapngRecorder> raw;
  DiscardRecords discard;
  try {
    const std::string port = port_of(args);
    if (args.link_type != extcap::kLinkFrames && args.link_type != extcap::kLinkRaw) {
      throw InputError(fmt::format("extcap: --link-type: expected {} or {}, found '{}'",
                                   extcap::kLinkFrames, extcap::kLinkRaw, args.link_type));
    }
    ReplayOptions line = line_options(args);
    const auto devices = args.devices.build_with_maps(line);

    LiveSessionSetup session;
    LiveOptions& options = session.capture;
    options.ports = {port};
    options.line.baud = line.overrides.baud.value_or(options.line.baud);
    options.line.parity = line.overrides.parity.value_or(options.line.parity);
    options.line.stop_bits = line.overrides.stop_bits.value_or(options.line.stop_bits);
    options.response_timeout = line.response_timeout;
    session.prefix = "rtuscope extcap";

    if (args.link_type == extcap::kLinkFrames) {
      frames = std::make_unique<PcapExportSink>(std::move(pipe), PcapExportOptions{});
      session.frames_sink = frames.get();
    } else {
      raw = std::make_unique<PcapngRecorder>(std::move(pipe), args.fifo);
      session.chunk_recorder = raw.get();
      session.frames_sink = &discard;
    }

    LiveSessionHooks hooks;
    // Wireshark closes the FIFO first, then sends SIGTERM (which the session handles).
    hooks.finished = [&reader] { return reader.reader_gone(); };
    // Wireshark shows anything on stderr as an error of the capture: notes (a port that
    // cannot do low latency, an adapter unplugged and back) are for `rtuscope live`.
    hooks.on_note = [](const std::string&) {};
    run_live_session(session, *devices, hooks);
  } catch (const std::exception& e) {
    fmt::print(stderr, "rtuscope: {}\n", e.what());
    std::fflush(stderr);
    return 2;
  }
  return 0;
}

void run_extcap(const ExtcapArgs& args, int& exit_code) {
  if (args.list_interfaces) {
    fmt::print("{}", extcap::interfaces_text(listed_ports(), RTUSCOPE_VERSION));
  } else if (args.dlts) {
    (void)port_of(args);
    fmt::print("{}", extcap::dlts_text());
  } else if (args.config) {
    (void)port_of(args);
    fmt::print("{}", extcap::config_text());
  } else if (args.capture) {
    exit_code = run_capture(args);
    return;
  } else {
    throw InputError(
        "extcap: expected one of --extcap-interfaces, --extcap-dlts, --extcap-config or "
        "--capture (Wireshark calls this; to install it, run tools/install-extcap.sh)");
  }
  std::fflush(stdout);
  exit_code = 0;
}

void setup_extcap(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<ExtcapArgs>();
  auto* cmd = app.add_subcommand(
      "extcap",
      "Wireshark capture interface (extcap): lists the serial ports in Wireshark and streams "
      "their live decode to it. Install with tools/install-extcap.sh");
  // Wireshark may add arguments newer than this code; they are ignored, not refused.
  cmd->allow_extras();
  cmd->add_flag("--extcap-interfaces", args->list_interfaces, "List the interfaces");
  cmd->add_option("--extcap-version", args->wireshark_version, "Wireshark's version")
      ->expected(0, 1);
  cmd->add_option("--extcap-interface", args->interface, "The interface (rtuscope/PATH)");
  cmd->add_flag("--extcap-dlts", args->dlts, "List the interface's link types");
  cmd->add_flag("--extcap-config", args->config, "List the interface's options");
  cmd->add_flag("--capture", args->capture, "Capture into --fifo");
  cmd->add_option("--fifo", args->fifo, "The pipe Wireshark reads");
  cmd->add_option("--extcap-capture-filter", args->capture_filter, "Ignored: no filters");
  cmd->add_option("--extcap-control-in", args->control_in, "Ignored: no toolbar");
  cmd->add_option("--extcap-control-out", args->control_out, "Ignored: no toolbar");
  cmd->add_option("--extcap-reload-option", args->reload_option, "Ignored");
  cmd->add_flag("--debug", args->debug, "Ignored");
  cmd->add_option("--debug-file", args->debug_file, "Ignored");
  cmd->add_option("--baud", args->baud, "Baud rate (default: the bus file's, else 9600)")
      ->check(CLI::Range(50U, 20000000U));
  cmd->add_option("--parity", args->parity, "E|N|O, or auto: the bus file's, else E");
  cmd->add_option("--stop", args->stop, "1|2, or auto: the bus file's, else 1");
  cmd->add_option("--timeout-ms", args->timeout_ms,
                  "Response timeout in ms (default: the bus file's, else 1000)")
      ->check(CLI::PositiveNumber);
  args->devices.add_to(*cmd);
  cmd->add_option("--link-type", args->link_type,
                  "frames: decoded frames (LINKTYPE 252, as `export`); raw: reads and line "
                  "events (LINKTYPE 250, as `live -w`)");
  cmd->callback([args, &exit_code] { run_extcap(*args, exit_code); });
}

RTUSCOPE_REGISTER_COMMAND(setup_extcap);

}  // namespace
}  // namespace rtu::app
