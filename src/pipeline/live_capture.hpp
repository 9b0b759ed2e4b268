#pragma once
// Live capture: one or two serial ports read with Boost.Asio, decoded as they arrive by the
// same DecodePipeline that replays files, and optionally recorded chunk by chunk.
//
//  * Chunks of all ports are stamped on arrival on one CaptureClock and handled on one
//    thread, so they reach the pipeline merged in time order. With two ports (the two
//    directions of an RS-232/RS-422 link) each chunk keeps its port index for recorders.
//  * A timer calls DecodePipeline::idle() a little (LiveOptions::idle_slack) after what the
//    pipeline holds can first be decided (DecodePipeline::next_idle_decision), so a frame is
//    printed once the line has been quiet long enough, not when more bytes come; with nothing
//    undecided it sleeps until the next read. The pipeline decides at the same point of the byte
//    stream as a replay of the recording.
//  * A port that fails (USB adapter unplugged) is reported, recorded as a gap, and reopened
//    every `reopen_period` until it comes back; the capture goes on.
//  * stop() (SIGINT/SIGTERM in the command) closes the ports and flushes everything.
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "framing/record.hpp"
#include "pipeline/decode_pipeline.hpp"
#include "serial/clock.hpp"
#include "serial/serial_source.hpp"

namespace rtu {

// Receives everything read, exactly as read (e.g. a capture file writer).
class ChunkRecorder {
 public:
  virtual ~ChunkRecorder() = default;
  // Called once per port before any chunk: its name and settings as opened, and the
  // response timeout the capture is decoded with.
  virtual void add_port(std::size_t port, const std::string& name, const LineSettings& line,
                        const SerialStatus& status, Nanos response_timeout) = 0;
  virtual void on_chunk(std::size_t port, const Chunk& chunk) = 0;
  // The port stopped delivering at `t` (unplugged); bytes may have been lost until it
  // comes back.
  virtual void on_gap(std::size_t port, Nanos t, const std::string& reason) = 0;
  // The capture stopped at `t` (called once, before the last flush).
  virtual void on_end(Nanos t) = 0;
  // Called at least every second and at the end: makes what was recorded durable.
  virtual void flush() = 0;
};

struct LiveOptions {
  std::vector<std::string> ports;  // one or two
  LineSettings line;
  Nanos response_timeout = 1000 * kNanosPerMilli;
  Nanos idle_period = 5 * kNanosPerMilli;
  // How much later than the first possible moment the idle timer decides. A read that comes
  // meanwhile decides the same, at no wake-up of its own, so on a busy line the timer wakes
  // up about once per slack instead of after every frame; on a quiet one a frame is printed
  // this much later. What is decided never depends on it (DecodePipeline::idle).
  Nanos idle_slack = 20 * kNanosPerMilli;
  Nanos reopen_period = 1 * kNanosPerSecond;
  Nanos flush_period = 500 * kNanosPerMilli;
  Nanos duration = 0;                 // stop by itself after this long; 0 = until stop()
  std::vector<std::string> warnings;  // for the header (CaptureInfo::warnings)
};

struct LiveSummary {
  std::uint64_t chunks = 0;
  std::uint64_t bytes = 0;
  std::uint64_t frames = 0;
  std::uint64_t noise_records = 0;
  std::uint64_t crc_errors = 0;
  std::uint64_t transactions = 0;  // responses paired with their request
  std::uint64_t timeouts = 0;
  std::uint64_t frames_with_issues = 0;
  std::uint64_t line_error_bytes = 0;
  std::uint64_t disconnects = 0;
  std::uint64_t idle_wakeups = 0;     // times the idle timer woke the capture up
  std::uint64_t late_reads = 0;       // reads the host made late (Chunk::read_late)
  std::uint64_t reconnects = 0;       // ports opened again after a disconnect
  Nanos last_byte_at = kUnknownTime;  // capture time of the last read that had bytes
  Nanos duration = 0;
  Nanos declared_resolution = 0;  // what the ports promised when opened
  Nanos timing_resolution = 0;    // what the reads showed (never below the promise)
};

// A port lost (unplugged) or back, for the event log.
struct PortEvent {
  bool back = false;   // false: lost
  std::string port;    // its path
  std::string reason;  // why it was lost ("" when back)
  Nanos t = 0;         // capture time
};

class LiveCapture {
 public:
  using PortListener = std::function<void(const PortEvent& event)>;

  // `notify` receives one-line messages for the user (port notes, unplug/replug).
  using Notify = std::function<void(const std::string& message)>;

  LiveCapture(boost::asio::io_context& io, Clock& clock, LiveOptions options, RecordSink& sink,
              ChunkRecorder* recorder, Notify notify);
  ~LiveCapture();
  LiveCapture(const LiveCapture&) = delete;
  LiveCapture& operator=(const LiveCapture&) = delete;

  void set_port_listener(PortListener listener) { port_listener_ = std::move(listener); }
  // Opens every port (throws SerialOpenError) and starts reading and the timers.
  void start();
  // Stops reading, decides what is pending, flushes. Idempotent.
  void stop();
  [[nodiscard]] bool stopped() const { return stopped_; }
  [[nodiscard]] const LiveSummary& summary() const { return summary_; }
  [[nodiscard]] const CaptureInfo& info() const { return info_; }
  // Capture time now, on the clock the chunks are stamped with (ns since 1970).
  [[nodiscard]] Nanos now() { return clock_.now(); }

 private:
  class Counter;
  struct Port;

  void start_port(Port& port);
  void on_chunk(Port& port, const Chunk& chunk);
  void on_port_error(Port& port, const std::error_code& error);
  void schedule_reopen(Port& port);
  void arm_idle_for_pipeline();
  void schedule_idle(Nanos delay);
  void schedule_flush();
  void note_ports_free();

  boost::asio::io_context& io_;
  CaptureClock clock_;
  LiveOptions options_;
  ChunkRecorder* recorder_;
  Notify notify_;
  PortListener port_listener_;
  std::unique_ptr<Counter> counter_;
  std::unique_ptr<DecodePipeline> pipeline_;
  std::vector<std::unique_ptr<Port>> ports_;
  boost::asio::steady_timer idle_timer_;
  bool idle_armed_ = false;        // the idle timer runs (see arm_idle_for_pipeline)
  Nanos idle_due_ = kUnknownTime;  // when it fires, on clock_
  boost::asio::steady_timer flush_timer_;
  boost::asio::steady_timer stop_timer_;
  CaptureInfo info_;
  LiveSummary summary_;
  Nanos started_at_ = 0;
  bool stopped_ = false;
};

}  // namespace rtu
