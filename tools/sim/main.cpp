// rtusim: writes simulated Modbus RTU bus captures with exact ground truth.
// Argument parsing and wiring only; the bus, the devices, the faults, the adapter model and
// the writers each live in their own file.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bus_simulator.hpp"
#include "device_profile.hpp"
#include "hex_writer.hpp"
#include "recording_writer.hpp"
#include "saleae_writer.hpp"
#include "truth_writer.hpp"
#include "usb_adapter_model.hpp"

namespace {

using namespace rtu::sim;  // NOLINT(google-build-using-namespace): a tool's main

constexpr std::uint64_t kUsbStream = 0x05B;

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

// The command as a user would retype it: program name without its directory.
std::string provenance(int argc, char** argv) {
  std::string cmd = "rtusim";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool plain = arg.find_first_of(" \t\"'\\$`") == std::string::npos && !arg.empty();
    cmd += ' ';
    cmd += plain ? arg : "'" + arg + "'";
  }
  return cmd;
}

std::ofstream open_output(const std::string& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(fmt::format("cannot write {}", path));
  return out;
}

rtu::Nanos seconds_to_nanos(double s) {
  return static_cast<rtu::Nanos>(std::llround(s * 1e9));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"rtusim: simulated Modbus RTU bus traffic with exact ground truth"};
  std::string out_path;
  std::string truth_path;
  std::string saleae_path;
  std::string pcapng_path;
  std::string chunking = "perbyte";
  std::uint64_t seed = 1;
  double duration_s = 0;
  std::uint64_t transactions = 0;
  std::uint32_t baud = 9600;
  std::string parity = "E";
  unsigned stop = 1;
  double fault_rate = 0;
  std::string profile = "classic";
  std::string fault_kinds;
  std::string devices_arg;
  double latency_ms = 16;
  std::size_t packet = 62;
  double jitter_us = 2000;
  double usb_frame_us = 1000;
  double idle_chars = 4;
  double cycle_ms = 500;
  double master_timeout_ms = 200;
  double start_s = 0;

  app.add_option("--out", out_path, "text hex capture to write (FILE.hex)");
  app.add_option("--truth", truth_path, "ground truth to write (FILE.jsonl)");
  app.add_option("--saleae", saleae_path, "Saleae Logic 2 data-table export to write (FILE.csv)");
  app.add_option("--pcapng", pcapng_path,
                 "the same reads as --out, recorded as `rtuscope live -w` records them "
                 "(FILE.pcapng; the timing resolution declared, no response timeout)");
  app.add_option("--chunking", chunking,
                 "perbyte: one byte per line; usb: FTDI-like reads (a latency timer); idle: "
                 "reads an adapter sends once the line is idle (--idle-chars)")
      ->check(CLI::IsMember({"perbyte", "usb", "idle"}));
  app.add_option("--seed", seed, "random seed; same seed and options give identical files");
  app.add_option("--duration", duration_s, "stop after this many seconds of traffic")
      ->check(CLI::PositiveNumber);
  app.add_option("--transactions", transactions, "stop after this many transactions")
      ->check(CLI::PositiveNumber);
  app.add_option("--baud", baud, "line speed")->check(CLI::Range(300U, 4'000'000U));
  app.add_option("--parity", parity, "N, E or O")->check(CLI::IsMember({"N", "E", "O"}));
  app.add_option("--stop", stop, "stop bits, 1 or 2")->check(CLI::IsMember({1U, 2U}));
  auto* faults_option =
      app.add_option("--faults", fault_rate,
                     "share of transactions that get a fault (0 = clean; default 0, or 0.1 "
                     "with --profile heavy)")
          ->check(CLI::Range(0.0, 1.0));
  app.add_option("--profile", profile,
                 "classic: one fault per faulty transaction; heavy: a sick bus, one or two "
                 "faults per faulty transaction, damage in any byte, noise touching frames, "
                 "glitch bytes, early responses, absent slaves")
      ->check(CLI::IsMember({"classic", "heavy"}));
  app.add_option("--fault-kinds", fault_kinds,
                 "comma-separated subset of crc,noise,turnaround,truncated,timeout,exception,"
                 "pause,short_gap,broadcast,wrong_slave (default: all); with --profile heavy "
                 "a subset of turnaround,truncated,timeout,exception,pause,short_gap,"
                 "broadcast,wrong_slave,bitflip,noise_before,noise_after,noise_gap,glitch,"
                 "fast_response,dead_slave (default: all)");
  app.add_option("--devices", devices_arg,
                 "comma-separated subset of yw2050,yw2300,th900,yakotec,generic (default: all)");
  app.add_option("--latency-ms", latency_ms, "USB adapter latency timer")
      ->check(CLI::Range(1.0, 255.0));
  app.add_option("--packet", packet, "USB packet data bytes")->check(CLI::Range(1, 510));
  app.add_option("--jitter-us", jitter_us, "host scheduling jitter, maximum")
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--usb-frame-us", usb_frame_us, "USB frame period (1000 full speed, 125 high)")
      ->check(CLI::Range(1.0, 1e4));
  app.add_option("--idle-chars", idle_chars,
                 "with --chunking idle: character times of idle line after which the adapter "
                 "sends what it holds")
      ->check(CLI::Range(0.5, 1000.0));
  app.add_option("--cycle-ms", cycle_ms, "poll cycle period of the master")
      ->check(CLI::Range(1.0, 1e6));
  app.add_option("--master-timeout-ms", master_timeout_ms,
                 "how long the master waits for an answer")
      ->check(CLI::Range(1.0, 1e5));
  app.add_option("--start", start_s, "time of the first poll, seconds")
      ->check(CLI::Range(0.0, 1e9));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }

  try {
    if (out_path.empty() && truth_path.empty() && saleae_path.empty() && pcapng_path.empty()) {
      throw std::runtime_error("nothing to write: give --out, --pcapng, --truth and/or --saleae");
    }
    BusOptions opt;
    opt.line.baud = baud;
    opt.line.parity = *rtu::parse_parity(parity);
    opt.line.stop_bits = static_cast<std::uint8_t>(stop);
    opt.seed = seed;
    if (transactions > 0) opt.transactions = transactions;
    if (duration_s > 0) opt.duration = seconds_to_nanos(duration_s);
    if (!opt.transactions && !opt.duration) opt.transactions = 200;
    opt.start = seconds_to_nanos(start_s);
    opt.cycle_period = seconds_to_nanos(cycle_ms / 1e3);
    opt.master_timeout = seconds_to_nanos(master_timeout_ms / 1e3);
    const bool heavy = profile == "heavy";
    opt.profile = heavy ? FaultProfile::kHeavy : FaultProfile::kClassic;
    opt.fault_rate = fault_rate;
    if (heavy && faults_option->count() == 0) opt.fault_rate = 0.1;
    if (fault_kinds.empty()) {
      opt.fault_kinds = heavy ? heavy_faults() : all_faults();
    } else {
      const auto& allowed = heavy ? heavy_faults() : all_faults();
      for (const auto& name : split_list(fault_kinds)) {
        const auto f = parse_fault(name);
        if (!f) throw std::runtime_error(fmt::format("--fault-kinds: unknown fault '{}'", name));
        if (std::find(allowed.begin(), allowed.end(), *f) == allowed.end()) {
          throw std::runtime_error(
              fmt::format("--fault-kinds: '{}' is not a fault of --profile {}", name, profile));
        }
        opt.fault_kinds.push_back(*f);
      }
    }
    std::vector<std::unique_ptr<DeviceProfile>> devices;
    for (const auto& name : devices_arg.empty() ? device_names() : split_list(devices_arg)) {
      auto device = make_device(name);
      if (!device) {
        throw std::runtime_error(fmt::format("--devices: unknown device '{}' (known: {})", name,
                                             fmt::join(device_names(), ",")));
      }
      devices.push_back(std::move(device));
    }
    if (devices.empty()) throw std::runtime_error("--devices: no device given");

    const Timeline timeline = simulate_bus(opt, devices);
    const std::string command = provenance(argc, argv);

    if (!out_path.empty() || !pcapng_path.empty()) {
      std::vector<OutputChunk> chunks;
      // What a live run would declare: the adapter's latency timer; for reads of one byte
      // each, stamped exactly, the finest resolution rtuscope takes (1 µs).
      rtu::Nanos resolution = rtu::kNanosPerMicro;
      if (chunking == "usb" || chunking == "idle") {
        UsbAdapterModel model;
        model.latency = seconds_to_nanos(latency_ms / 1e3);
        model.packet = packet;
        model.jitter = seconds_to_nanos(jitter_us / 1e6);
        model.usb_frame = seconds_to_nanos(usb_frame_us / 1e6);
        if (chunking == "idle") {
          model.idle_flush =
              static_cast<rtu::Nanos>(idle_chars * static_cast<double>(opt.line.char_time()));
        }
        chunks = chunk_usb(timeline.bytes(), model, Rng(seed).fork(kUsbStream));
        // How late a read may come after its bytes: the idle wait, a USB frame and the wake-up.
        resolution =
            chunking == "usb" ? model.latency : model.idle_flush + model.usb_frame + model.jitter;
      } else {
        chunks = chunk_per_byte(timeline.bytes());
      }
      if (!out_path.empty()) {
        auto out = open_output(out_path);
        write_hex_capture(out, opt.line, command, timeline.bytes(), chunks);
      }
      if (!pcapng_path.empty()) {
        write_read_recording(pcapng_path, opt.line, resolution, timeline.bytes(), chunks);
      }
    }
    if (!saleae_path.empty()) {
      auto out = open_output(saleae_path);
      write_saleae_table(out, timeline.bytes());
    }
    if (!truth_path.empty()) {
      auto out = open_output(truth_path);
      write_truth(out, opt.line, command, timeline);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "rtusim: {}\n", e.what());
    return 2;
  }
  return 0;
}
