#pragma once
// A virtual RS-485 bus on pseudo-terminals, for tests and the demo: N endpoints, each a
// pty whose slave path a program opens like a serial port. Every byte written on one
// endpoint is delivered to all the others, one character time after the previous byte on
// the line (the bus is half-duplex and shared: bytes of simultaneous writers are
// serialised in arrival order, as an arbitration-free RS-485 line would garble them).
//
// Options: fault injection (a random bit flipped in a delivered byte, per byte with a
// given probability, seeded), and USB-style chunking toward chosen endpoints (bytes held
// until a 62-byte packet fills or a latency timer expires, as FTDI adapters do).
//
// Emulated UARTs (any of listen_as, talk_as, invert, bias_glitches): each byte written is
// drawn as a bit stream at its writer's settings (uart_line.hpp) and each endpoint gets what
// a UART at its own settings makes of the line: bytes, parity and framing errors, breaks.
// Errors reach a program that set PARMRK in the form n_tty gives them (FF 00 x, FF 00 00
// for a break, FF FF for a data FF; FORMATS §7.1). A pty cannot carry error flags, so the
// bus clears PARMRK on that pty itself and writes the marks the kernel would have made.
// Without these options the bus relays bytes exactly as it always has.
//
// The bus log records every byte written, by whom and when it was on the wire (monotonic
// ns), one entry per burst; faults and late deliveries (the bus's thread woke late, so an
// endpoint got bytes later than the wire had them) are logged separately. It is the ground truth
// tests compare a capture with.
#include <atomic>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/time.hpp"
#include "serial/line_settings.hpp"
#include "serial/uart_line.hpp"

namespace rtu {

// How one endpoint's UART is set.
struct EndpointUart {
  // Follow the settings the program on the endpoint gave its pty (termios). A pty keeps
  // the speed, CSTOPB and PARODD but always clears PARENB, so odd parity shows and even
  // does not: without PARODD, one stop bit reads as 8E1 and two as 8N2 (the Modbus rule).
  bool follow_pty = false;
  LineSettings line;  // when not following the pty
};

struct VirtualBusOptions {
  std::size_t endpoints = 3;
  LineSettings line;  // pacing: one character per line.char_time()
  // false: the bytes of one read from a writer (usually a whole frame) are delivered
  // together when its last byte has crossed the line, so a frame is never torn apart by
  // this process being descheduled between two of its bytes (which happens on a loaded
  // host: pacing by sleeps is only as good as the scheduler). true: byte by byte.
  bool per_byte = false;
  double flip_probability = 0.0;  // per delivered byte
  std::uint32_t seed = 1;
  std::vector<std::size_t> usb_endpoints;  // endpoints that receive USB-style chunks
  Nanos usb_latency = 16 * kNanosPerMilli;
  std::size_t usb_packet = 62;
  // Emulated UARTs (see above); an endpoint not named takes the bus's `line`.
  std::map<std::size_t, EndpointUart> listen_as;  // what each endpoint receives at
  std::map<std::size_t, EndpointUart> talk_as;    // what each endpoint transmits at
  bool invert = false;         // A and B swapped: every level inverted, the idle line is 0
  bool bias_glitches = false;  // an unbiased line: a one-bit low pulse at each turnaround
  std::string log_path;        // bus log as a text hex capture ("" = none)
  std::string link_dir;        // symlinks <dir>/ep0 ... to the endpoints ("" = none)
};

struct BusLogEntry {
  std::size_t from = 0;
  Nanos t_start = 0;  // wire time of the first byte's start (monotonic clock)
  Nanos t_end = 0;    // end of the last byte
  std::vector<std::uint8_t> bytes;
};

class VirtualBus {
 public:
  // Creates the pseudo-terminals. Throws std::system_error when it cannot.
  explicit VirtualBus(VirtualBusOptions options);
  ~VirtualBus();
  VirtualBus(const VirtualBus&) = delete;
  VirtualBus& operator=(const VirtualBus&) = delete;

  // Paths programs open (/dev/pts/N, or the symlinks when link_dir is set).
  [[nodiscard]] const std::vector<std::string>& paths() const { return paths_; }

  // Runs the bus on a thread of its own until stop() (or the destructor).
  void start();
  // Runs the bus on the calling thread until stop() is called from elsewhere. After
  // stop() the bus cannot run again.
  void run();
  void stop();

  // Removes the endpoint as if its adapter were unplugged (its users see a hang-up), and
  // plugs in a new one under the same link (needs link_dir).
  void unplug(std::size_t endpoint);
  void replug(std::size_t endpoint);

  // A copy of the log so far (thread-safe).
  [[nodiscard]] std::vector<BusLogEntry> log() const;
  [[nodiscard]] std::uint64_t flipped_bytes() const { return flipped_.load(); }
  [[nodiscard]] std::uint64_t dropped_bytes() const { return dropped_.load(); }

 private:
  struct Endpoint;
  struct Pending {
    Nanos t_end;
    std::size_t from;
    std::uint8_t byte;
  };

  void open_endpoint(std::size_t index);
  void close_endpoint(std::size_t index);
  void read_from(std::size_t index, Nanos now);
  void deliver_due(Nanos now);
  void flush_usb(std::size_t index, Nanos now, bool force);
  void write_to(std::size_t index, const std::uint8_t* data, std::size_t n);
  [[nodiscard]] bool emulating() const;
  [[nodiscard]] LineSettings uart_of(std::size_t index, bool transmit) const;
  Nanos render_burst_start(std::size_t writer, Nanos t, const LineSettings& tx);
  void deliver_emulated(Nanos now, std::optional<Nanos> line_known_until);
  void receive_at(std::size_t index, Picos known_until);
  void put_received(std::size_t index, const ReceivedChar& c);
  std::uint8_t maybe_flip(std::uint8_t byte, std::size_t to);
  [[nodiscard]] Picos to_picos(Nanos t) const { return (t - origin_) * 1000; }
  [[nodiscard]] Nanos to_nanos(Picos t) const { return origin_ + (t + 999) / 1000; }
  void log_entry(const BusLogEntry& entry);
  void log_late_delivery(std::size_t to, Nanos wire_end, Nanos now);
  // Deliveries later than this after the wire end of their first byte are logged.
  static constexpr Nanos kLateDeliveryLogged = 250 * kNanosPerMicro;

  VirtualBusOptions options_;
  std::vector<Endpoint> endpoints_;
  std::vector<std::string> paths_;
  std::vector<Pending> queue_;  // in wire order
  std::size_t queue_head_ = 0;
  Nanos line_free_at_ = 0;
  Nanos char_time_ = 0;
  std::uint64_t rng_state_;

  // Emulated UARTs: the line as drawn so far, on a picosecond timeline from origin_.
  struct Burst {
    std::size_t from;
    Picos start;
    Picos end;
  };
  Nanos origin_ = 0;
  LineLevels line_;
  Picos line_end_ = 0;        // end of the last character drawn
  Picos line_known_ = 0;      // the line up to here has been received by every endpoint
  std::deque<Burst> bursts_;  // who drew what, so no endpoint receives its own bytes
  std::size_t last_writer_ = static_cast<std::size_t>(-1);
  Nanos uart_wake_ = -1;  // when a character begun on the line will be whole

  mutable std::mutex mutex_;  // guards log_, endpoints_ fds during unplug/replug
  std::vector<BusLogEntry> log_;
  std::FILE* log_file_ = nullptr;
  int wake_pipe_[2] = {-1, -1};
  std::atomic<bool> running_{false};
  std::atomic<std::uint64_t> flipped_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::thread thread_;
};

// Opens an endpoint as a peer on the bus does, raw (the bytes written are the bytes the bus
// carries), and returns its file descriptor for the caller to close. Throws InputError when
// the endpoint cannot be opened.
[[nodiscard]] int open_bus_endpoint(const std::string& path);

}  // namespace rtu
