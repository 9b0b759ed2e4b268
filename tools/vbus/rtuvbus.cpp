// rtuvbus: a virtual RS-485 bus on pseudo-terminals. Prints one endpoint path per line,
// then relays every byte written on an endpoint to all the others at the line's pace,
// until SIGINT or SIGTERM.
//
//   rtuvbus -n 3 --baud 19200 --parity E --log bus.hex [--link-dir DIR] [--flip P]
//           [--usb EP]... [--usb-latency-ms 16] [--usb-packet 62]
//           [--listen-as EP=19200:8E1|EP=tty]... [--talk-as EP=...]... [--invert]
//           [--bias-glitches]
#include <fmt/format.h>
#include <signal.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "serial/virtual_bus.hpp"

namespace {

// "2=19200:8E1" or "2=tty" into the table; false when malformed.
bool add_endpoint_uart(const std::string& text, std::size_t endpoints,
                       std::map<std::size_t, rtu::EndpointUart>& table) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) return false;
  std::size_t index = 0;
  try {
    std::size_t used = 0;
    index = std::stoul(text.substr(0, eq), &used);
    if (used != eq || index >= endpoints) return false;
  } catch (const std::exception&) {
    return false;
  }
  rtu::EndpointUart uart;
  const std::string spec = text.substr(eq + 1);
  if (spec == "tty") {
    uart.follow_pty = true;
  } else {
    const auto line = rtu::parse_line_spec(spec);
    if (!line) return false;
    uart.line = *line;
  }
  table[index] = uart;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"rtuvbus: virtual RS-485 bus on pseudo-terminals"};
  rtu::VirtualBusOptions options;
  std::string parity = "E";
  unsigned stop_bits = 1;
  double usb_latency_ms = 16.0;
  app.add_option("-n,--endpoints", options.endpoints, "Number of endpoints (default 3)")
      ->check(CLI::Range(2, 32));
  app.add_option("--baud", options.line.baud, "Baud rate for pacing (default 9600)")
      ->check(CLI::Range(50U, 20000000U));
  app.add_option("--parity", parity, "Parity N|E|O: character time for pacing (default E)");
  app.add_option("--stop", stop_bits, "Stop bits 1|2 (default 1)")->check(CLI::IsMember({1U, 2U}));
  app.add_flag("--per-byte", options.per_byte,
               "Deliver byte by byte at the line rate (default: each read of a writer at once, "
               "when its last byte has crossed the line)");
  app.add_option("--log", options.log_path, "Bus log: every byte written, by whom and when");
  app.add_option("--link-dir", options.link_dir, "Create symlinks DIR/ep0, DIR/ep1, ...");
  app.add_option("--flip", options.flip_probability,
                 "Fault injection: probability per delivered byte of one flipped bit")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--seed", options.seed, "Seed of the fault injection (default 1)");
  app.add_option("--usb", options.usb_endpoints,
                 "Endpoint index that receives USB-style chunks (repeatable)");
  app.add_option("--usb-latency-ms", usb_latency_ms, "USB latency timer (default 16)")
      ->check(CLI::PositiveNumber);
  app.add_option("--usb-packet", options.usb_packet,
                 "USB packet size: a full packet is sent at once (default 62, as FTDI)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{4096}));
  std::vector<std::string> listen_as;
  std::vector<std::string> talk_as;
  app.add_option("--listen-as", listen_as,
                 "EP=BAUD:8E1 or EP=tty: what endpoint EP's UART receives at (tty: the "
                 "settings its program gave the pty, which drops PARENB, so 8E1 and 8N1 both "
                 "read as 8E1); the line is then emulated bit by bit (repeatable)");
  app.add_option("--talk-as", talk_as,
                 "EP=BAUD:8E1 or EP=tty: what endpoint EP transmits at (repeatable)");
  app.add_flag("--invert", options.invert,
               "A and B swapped: every level on the wire inverted (the idle line is 0)");
  app.add_flag("--bias-glitches", options.bias_glitches,
               "Unbiased line: a one-bit low pulse each time another endpoint takes the line");
  CLI11_PARSE(app, argc, argv);
  for (const auto& [texts, table, name] :
       {std::tuple{&listen_as, &options.listen_as, "--listen-as"},
        std::tuple{&talk_as, &options.talk_as, "--talk-as"}}) {
    for (const auto& text : *texts) {
      if (!add_endpoint_uart(text, options.endpoints, *table)) {
        fmt::print(stderr, "rtuvbus: {} {}: expected EP=BAUD:8E1 (N|E|O, 1|2) or EP=tty\n", name,
                   text);
        return 2;
      }
    }
  }
  const auto p = rtu::parse_parity(parity);
  if (!p) {
    fmt::print(stderr, "rtuvbus: --parity: expected N, E or O\n");
    return 2;
  }
  options.line.parity = *p;
  options.line.stop_bits = static_cast<std::uint8_t>(stop_bits);
  options.usb_latency = static_cast<rtu::Nanos>(usb_latency_ms * 1e6);

  // Signals are taken synchronously by a waiting thread, so the bus loop never sees them.
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  try {
    rtu::VirtualBus bus(options);
    for (const auto& path : bus.paths()) fmt::print("{}\n", path);
    std::fflush(stdout);
    bus.start();
    int sig = 0;
    sigwait(&set, &sig);
    bus.stop();
    fmt::print(stderr, "rtuvbus: {} bursts relayed, {} bytes flipped, {} bytes dropped\n",
               bus.log().size(), bus.flipped_bytes(), bus.dropped_bytes());
  } catch (const std::exception& e) {
    fmt::print(stderr, "rtuvbus: {}\n", e.what());
    return 2;
  }
  return 0;
}
