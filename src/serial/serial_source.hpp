#pragma once
// Live input from a serial port: Boost.Asio `serial_port` with asynchronous reads. Each read
// becomes one Chunk stamped on arrival (CaptureClock: monotonic gaps, wall-clock epoch).
// rtuscope never transmits on the port.
//
// Configuration (FORMATS §7): 8 data bits, no flow control, the requested stop bits and
// parity through Asio; any baud rate (termios2/BOTHER when Asio's table lacks it); then,
// after the last set_option, INPCK|PARMRK set and IGNPAR|IGNBRK|BRKINT|ISTRIP cleared
// through native_handle(), so bytes with parity/framing errors and breaks arrive marked
// instead of silently dropped; MarkDecoder turns the marks into per-byte LineError flags,
// refined by TIOCGICOUNT deltas where the driver keeps counters. Low latency is requested
// (ASYNC_LOW_LATENCY, FTDI latency_timer) and the timing resolution achieved is reported.
//
// Threading: everything runs on the io_context's thread; callbacks are called from it.
#include <boost/asio/io_context.hpp>
#include <boost/asio/serial_port.hpp>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "core/chunk.hpp"
#include "core/input_error.hpp"
#include "serial/clock.hpp"
#include "serial/late_read_check.hpp"
#include "serial/line_settings.hpp"
#include "serial/mark_decoder.hpp"
#include "serial/port_tuning.hpp"

namespace rtu {

struct SerialConfig {
  std::string path;
  LineSettings line;
  bool low_latency = true;
};

// What opening the port achieved. `notes` are one-line facts for the user (said once).
struct SerialStatus {
  std::uint32_t baud = 0;       // as read back from the driver (0 = unknown)
  bool parity_applied = false;  // false on devices without parity (pseudo-terminals)
  bool error_marking = false;   // PARMRK in effect: parity/framing/break errors are seen
  bool counters = false;        // TIOCGICOUNT available
  bool low_latency = false;
  std::optional<int> latency_timer_ms;  // FTDI latency timer, when the port has one
  // Smallest silence the chunk times can show: the adapter's delivery period where known
  // (FTDI latency timer), else the host's read timing (kHostReadResolution).
  Nanos resolution = 0;
  std::vector<std::string> notes;
};

// Read timing of a port with no batching timer of its own (UARTs, pseudo-terminals):
// wake-up and scheduling latency of the reading thread, typically well under this.
inline constexpr Nanos kHostReadResolution = 1 * kNanosPerMilli;

// A port that cannot be opened or configured; the message names it and says why.
class SerialOpenError : public InputError {
 public:
  SerialOpenError(const std::string& what, std::error_code code) : InputError(what), code_(code) {}
  [[nodiscard]] std::error_code code() const { return code_; }

 private:
  std::error_code code_;
};

class SerialSource {
 public:
  // `chunk` spans are valid only during the call.
  using ChunkHandler = std::function<void(const Chunk& chunk)>;
  // The port failed (e.g. the adapter was unplugged: EIO or end of file); reading stopped.
  using ErrorHandler = std::function<void(const std::error_code& error)>;

  SerialSource(boost::asio::io_context& io, CaptureClock& clock, SerialConfig config);
  ~SerialSource();
  SerialSource(const SerialSource&) = delete;
  SerialSource& operator=(const SerialSource&) = delete;

  // Opens and configures the port. Throws SerialOpenError (no such port, permission
  // denied, not a serial port). May be called again after a failure or close().
  const SerialStatus& open();
  // Starts reading; handlers are kept until close().
  void start(ChunkHandler on_chunk, ErrorHandler on_error);
  void close();
  [[nodiscard]] bool is_open() const { return port_.is_open(); }
  // Bytes the driver holds that no read has taken yet (0 when closed or unknown). The live
  // idle timer must not declare the line quiet while bytes wait here.
  [[nodiscard]] std::size_t pending_input();
  // Drops what the driver holds unread (bytes received at the settings before these).
  void discard_input();
  // A moment the reading thread is free (a timer's handler ends): when no input is pending,
  // the next read can have come late by no more than the thread's busy time from now on
  // (late_read_check.hpp). Keeps other work done meanwhile out of that bound.
  void note_free_moment();
  // The line was quiet up to `now` (capture time): the live idle timer found no input
  // pending then, and every read taken before that has been handled. A late read after it
  // carries that moment (Chunk::quiet_until), so a replay decides there too.
  void note_quiet_until(Nanos now);
  // Reads that came later than the timing resolution allows for (Chunk::read_late).
  [[nodiscard]] std::uint64_t late_reads() const { return late_check_.late_reads(); }
  [[nodiscard]] const SerialStatus& status() const { return status_; }
  [[nodiscard]] const SerialConfig& config() const { return config_; }

 private:
  void configure();
  void read_next();
  void note_waiting(bool input_pending);  // a moment the thread waits for bytes
  void on_read(const boost::system::error_code& error, std::size_t n);
  void refine_with_counters(std::size_t first_new);

  boost::asio::serial_port port_;
  CaptureClock& clock_;
  SerialConfig config_;
  SerialStatus status_;
  MarkDecoder decoder_;
  ChunkHandler on_chunk_;
  ErrorHandler on_error_;
  std::vector<std::uint8_t> raw_;
  std::vector<std::uint8_t> bytes_;
  std::vector<std::uint8_t> errors_;
  std::optional<LineCounters> counters_;
  std::uint64_t bytes_read_ = 0;
  LateReadCheck late_check_{kHostReadResolution};
  // The latest moment the port was seen empty, on the capture clock.
  Nanos quiet_seen_at_ = kUnknownTime;
  // Bytes were waiting in the port when it was opened: the first read takes them.
  bool queued_at_open_ = false;
};

}  // namespace rtu
