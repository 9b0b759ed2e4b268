#include "pipeline/line_probe.hpp"

#include <algorithm>
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>

#include "serial/clock.hpp"
#include "serial/serial_source.hpp"

namespace rtu {
namespace {

namespace asio = boost::asio;

bool same(const LineSettings& a, const LineSettings& b) {
  return a.baud == b.baud && a.parity == b.parity && a.stop_bits == b.stop_bits;
}

struct Listened {
  SettingEvidence evidence;
  std::vector<std::string> notes;
};

Listened listen_at(const std::string& port, const LineSettings& line, Nanos dwell) {
  asio::io_context io;
  SystemClock system_clock;
  CaptureClock clock(system_clock);
  SerialConfig config;
  config.path = port;
  config.line = line;
  SerialSource source(io, clock, config);
  const SerialStatus status = source.open();
  // Bytes still held were received at the previous setting.
  source.discard_input();
  EvidenceCounter counter(line, status.resolution);
  const Nanos start = clock.now();
  asio::steady_timer timer(io, std::chrono::nanoseconds(dwell));
  // The dwell is the most a setting gets: once the exchanges heard leave no doubt, the
  // probe moves on (the timer's handler runs at once when cancelled).
  source.start(
      [&counter, &timer](const Chunk& chunk) {
        counter.push(chunk);
        if (counter.settled()) timer.cancel();
      },
      [&io](const std::error_code&) { io.stop(); });
  timer.async_wait([&source](const boost::system::error_code&) { source.close(); });
  io.run();
  const Nanos stopped = clock.now();
  return {counter.finish(stopped - start, stopped), status.notes};
}

}  // namespace

std::vector<LineSettings> probe_candidates(bool quick) {
  const std::uint32_t rates[] = {1200,  2400,  4800,   9600,   14400,  19200, 38400,
                                 57600, 76800, 115200, 128000, 230400, 250000};
  const std::pair<Parity, std::uint8_t> framings[] = {
      {Parity::kEven, 1}, {Parity::kNone, 1}, {Parity::kOdd, 1}, {Parity::kNone, 2}};
  std::vector<LineSettings> all;
  if (quick) {
    // What Modbus devices ship with, most common first.
    for (const auto& s :
         {LineSettings{19200, Parity::kEven, 1}, LineSettings{9600, Parity::kEven, 1},
          LineSettings{9600, Parity::kNone, 1}, LineSettings{19200, Parity::kNone, 1},
          LineSettings{38400, Parity::kEven, 1}, LineSettings{115200, Parity::kEven, 1},
          LineSettings{115200, Parity::kNone, 1}, LineSettings{57600, Parity::kEven, 1},
          LineSettings{9600, Parity::kNone, 2}, LineSettings{19200, Parity::kNone, 2},
          LineSettings{4800, Parity::kEven, 1}, LineSettings{38400, Parity::kNone, 1}}) {
      all.push_back(s);
    }
  }
  for (const auto rate : rates) {
    for (const auto& [parity, stop] : framings) {
      const auto s = LineSettings{rate, parity, stop};
      if (std::none_of(all.begin(), all.end(), [&](const auto& t) { return same(s, t); })) {
        all.push_back(s);
      }
    }
  }
  return all;
}

ProbeRun run_probe(const ProbeOptions& options,
                   const std::function<void(const SettingEvidence&)>& on_setting,
                   const std::function<void()>& on_quiet) {
  ProbeRun run;
  const auto started = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return static_cast<Nanos>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                  std::chrono::steady_clock::now() - started)
                                  .count());
  };
  auto heard = [&](const LineSettings& s) -> SettingEvidence* {
    for (auto& e : run.table) {
      if (same(e.line, s)) return &e;
    }
    return nullptr;
  };
  auto listen = [&](const LineSettings& s) -> const SettingEvidence& {
    auto got = listen_at(options.port, s, options.dwell);
    for (const auto& note : got.notes) {
      if (std::find(run.notes.begin(), run.notes.end(), note) == run.notes.end()) {
        run.notes.push_back(note);
      }
    }
    SettingEvidence* old = heard(s);
    if (old != nullptr) {
      *old = got.evidence;  // a later pass over a quiet bus: the newer hearing counts
    } else {
      run.table.push_back(got.evidence);
      old = &run.table.back();
    }
    if (on_setting) on_setting(*old);
    return *old;
  };
  // Traffic at any rate shows as bytes or errors at every setting, so a few settings that
  // heard nothing at all mean a quiet bus, not a wrong setting.
  constexpr std::size_t kSilentSettingsForQuiet = 4;
  bool any_bytes = false;
  std::size_t silent = 0;
  bool done = false;
  while (!done) {
    for (const auto& candidate : options.candidates) {
      if (elapsed() + options.dwell > options.max_time) {
        done = true;
        break;
      }
      const SettingEvidence e = listen(candidate);
      any_bytes = any_bytes || e.bytes > 0;
      if (!any_bytes && ++silent == kSilentSettingsForQuiet && on_quiet) on_quiet();
      if (options.quick && e.reads_clean()) {
        // The other framings at this baud: a UART reads some of them alike, and the
        // errors of the others tell the parity.
        for (const auto& sibling : options.candidates) {
          if (sibling.baud != e.line.baud || heard(sibling) != nullptr) continue;
          if (elapsed() + options.dwell > options.max_time) break;
          listen(sibling);
        }
        done = true;
        break;
      }
    }
    if (any_bytes) break;
  }
  run.quiet = !any_bytes;
  run.elapsed = elapsed();
  return run;
}

}  // namespace rtu
