#pragma once
// The Prometheus metrics of one bus (`--metrics`): a RecordSink that sits beside the report's
// TrafficStats and renders both as exposition text when scraped.
//
// Most numbers are the report's own (TrafficStats: totals, per-slave requests, timeouts,
// exceptions, CRC errors, issues, point values), so a scrape and the report of the same run
// agree. This sink adds only what the report keeps in another shape: responses per function,
// latencies in fixed Prometheus buckets (0.5 ms to 2 s), and the line's busy time over the last
// 10 s. Every table is bounded: slaves are a byte, functions are a byte, and points are the
// report's (TrafficStats::kMaxPoints). Labels carry no free-form text: the bus name the user
// chose, numbers, function names, catalogue keys, model and point names from device maps.
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "framing/record.hpp"
#include "report/traffic_stats.hpp"

namespace rtu {

// The tool's own health, as the live session knows it at the time of a scrape.
struct ToolHealth {
  bool recording = false;                // a capture file is being written
  std::uint64_t capture_bytes = 0;       // bytes written to capture files, every file together
  std::uint64_t capture_files = 0;       // files started (rotations + 1)
  std::uint64_t capture_reopens = 0;     // files re-opened on request (SIGHUP)
  std::uint64_t read_bytes = 0;          // bytes read from the port(s)
  std::uint64_t disconnects = 0;         // ports lost
  std::uint64_t reconnects = 0;          // ports back after a loss
  double seconds_since_last_byte = NAN;  // NaN before the first byte
};

class BusMetrics final : public RecordSink {
 public:
  // Upper bounds of the latency histogram's buckets, in seconds: Modbus answers take from
  // under a millisecond (a fast slave at 115200 Bd) to the common 1-2 s master timeouts.
  static constexpr std::array<double, 14> kLatencyBounds = {
      0.0005, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0, 2.0};
  static constexpr Nanos kUtilisationWindow = 10 * kNanosPerSecond;

  // `stats` (not owned) is fed the same records elsewhere, by the report.
  BusMetrics(std::string bus, const TrafficStats& stats);
  ~BusMetrics() override;

  void on_capture(const CaptureInfo& info) override;
  void on_record(Record& record) override;

  // The exposition text (ExpositionWriter) at capture time `now`.
  [[nodiscard]] std::string exposition(Nanos now, const ToolHealth& health) const;

  // The line's busy share over the kUtilisationWindow before `now` (or since the first record
  // when that is later), 0..1.
  [[nodiscard]] double utilisation(Nanos now) const;

 private:
  struct SlaveExtras {
    std::map<std::uint8_t, std::uint64_t> responses;  // by function, exception bit cleared
    std::array<std::uint64_t, kLatencyBounds.size()> latency_le{};  // non-cumulative
    std::uint64_t latency_count = 0;
    double latency_sum = 0.0;          // seconds
    std::uint64_t latency_unseen = 0;  // answers in their request's read (latency_unseen())
  };
  struct BusySecond {
    std::int64_t second = -1;  // capture time / 1 s
    double busy_ns = 0.0;
  };

  std::string bus_;
  const TrafficStats& stats_;
  Nanos char_time_ = 0;
  Nanos first_t_ = kUnknownTime;
  std::array<std::unique_ptr<SlaveExtras>, 256> slaves_{};
  std::array<BusySecond, 11> busy_{};  // a ring, one second each
};

}  // namespace rtu
