#include "serial/serial_source.hpp"

#include <fmt/format.h>
#include <sys/ioctl.h>
#include <termios.h>

#include <boost/asio/buffer.hpp>
#include <cerrno>

#include "serial/custom_baud.hpp"

namespace rtu {
namespace {

namespace asio = boost::asio;
using Port = asio::serial_port;

constexpr std::size_t kReadSize = 4096;

std::string open_failure(const std::string& path, const boost::system::error_code& ec) {
  switch (ec.value()) {
    case ENOENT:
      return fmt::format("{}: no such serial port (is the adapter plugged in? see ls /dev/tty*)",
                         path);
    case EACCES:
    case EPERM:
      return fmt::format(
          "{}: permission denied (add yourself to the group owning the port, usually "
          "'dialout', then log in again)",
          path);
    case EBUSY: return fmt::format("{}: port is busy (another program has it open)", path);
    case ENOTTY: return fmt::format("{}: not a serial port", path);
    default: return fmt::format("{}: cannot open: {}", path, ec.message());
  }
}

}  // namespace

SerialSource::SerialSource(asio::io_context& io, CaptureClock& clock, SerialConfig config)
    : port_(io),
      clock_(clock),
      config_(std::move(config)),
      decoder_(config_.line.parity == Parity::kNone ? kFramingError : kParityError) {
  raw_.resize(kReadSize);
  bytes_.reserve(kReadSize);
  errors_.reserve(kReadSize);
}

SerialSource::~SerialSource() {
  close();
}

const SerialStatus& SerialSource::open() {
  close();
  status_ = SerialStatus{};
  boost::system::error_code ec;
  port_.open(config_.path, ec);
  if (ec) throw SerialOpenError(open_failure(config_.path, ec), ec);
  try {
    configure();
  } catch (...) {
    close();
    throw;
  }
  decoder_.reset();
  late_check_.restart(status_.resolution);
  quiet_seen_at_ = kUnknownTime;
  queued_at_open_ = pending_input() > 0;
  return status_;
}

void SerialSource::configure() {
  const std::string& path = config_.path;
  const int fd = port_.native_handle();
  termios probe{};
  if (::tcgetattr(fd, &probe) != 0) {
    const std::error_code ec(errno, std::generic_category());
    throw SerialOpenError(fmt::format("{}: not a serial port ({})", path, ec.message()), ec);
  }
  auto fail = [&](const char* what, const boost::system::error_code& ec) {
    throw SerialOpenError(fmt::format("{}: cannot set {}: {}", path, what, ec.message()),
                          std::error_code(ec.value(), std::generic_category()));
  };
  boost::system::error_code ec;
  port_.set_option(Port::character_size(8), ec);
  if (ec) fail("8 data bits", ec);
  port_.set_option(Port::flow_control(Port::flow_control::none), ec);
  if (ec) fail("no flow control", ec);
  port_.set_option(
      Port::stop_bits(config_.line.stop_bits == 2 ? Port::stop_bits::two : Port::stop_bits::one),
      ec);
  if (ec) fail("stop bits", ec);

  const Port::parity::type parity = config_.line.parity == Parity::kEven  ? Port::parity::even
                                    : config_.line.parity == Parity::kOdd ? Port::parity::odd
                                                                          : Port::parity::none;
  port_.set_option(Port::parity(parity), ec);
  if (ec && !(ec.value() == EINVAL && parity != Port::parity::none)) fail("parity", ec);
  // Pseudo-terminals have no parity: a tcsetattr whose only change is PARENB fails with
  // EINVAL, and one that changes more silently drops PARENB. Either way the bytes still
  // arrive; only parity checking is absent. Harmless, but said once.
  termios check{};
  status_.parity_applied =
      parity != Port::parity::none && ::tcgetattr(fd, &check) == 0 && (check.c_cflag & PARENB) != 0;
  if (parity != Port::parity::none && !status_.parity_applied) {
    status_.notes.push_back(
        fmt::format("{}: the device does not support parity (a pseudo-terminal?); parity "
                    "is not checked",
                    path));
  }

  bool custom = false;
  port_.set_option(Port::baud_rate(config_.line.baud), ec);
  if (ec) custom = true;  // not in Asio's table of B-constants: termios2 below

  // Error marking, after the last set_option (each set_option rewrites the flags).
  termios tio{};
  if (::tcgetattr(fd, &tio) == 0) {
    tio.c_iflag |= INPCK | PARMRK;
    tio.c_iflag &= ~static_cast<tcflag_t>(IGNPAR | IGNBRK | BRKINT | ISTRIP | IXON | IXOFF | ICRNL |
                                          INLCR | IGNCR);
    // Input flags belong to the line discipline, which keeps whatever it is given, so a
    // successful tcsetattr is the answer. A read-back is not: whoever else holds the port
    // may change it in between (rtuvbus takes PARMRK off a pseudo-terminal at once and
    // marks errors itself, and a read-back then said "no marks" while marks came).
    status_.error_marking = ::tcsetattr(fd, TCSANOW, &tio) == 0;
    if (!status_.error_marking) {
      status_.notes.push_back(fmt::format(
          "{}: cannot enable error marking ({}); bytes with parity or framing errors are "
          "not seen",
          path, std::error_code(errno, std::generic_category()).message()));
    }
  }
  if (custom) {
    if (const auto err = set_custom_baud(fd, config_.line.baud)) {
      throw SerialOpenError(
          fmt::format("{}: cannot set {} baud: {}", path, config_.line.baud, err.message()), err);
    }
  }
  status_.baud = read_baud(fd).value_or(0);
  if (status_.baud != 0 && status_.baud != config_.line.baud) {
    status_.notes.push_back(fmt::format("{}: the driver runs at {} baud ({} requested)", path,
                                        status_.baud, config_.line.baud));
  }

  int err = 0;
  counters_ = read_line_counters(fd, err);
  status_.counters = counters_.has_value();

  status_.resolution = kHostReadResolution;
  if (config_.low_latency) {
    int ll_err = 0;
    status_.low_latency = set_low_latency(fd, ll_err);
    bool lowered = false;
    status_.latency_timer_ms = tune_latency_timer(path, lowered);
    if (status_.latency_timer_ms) {
      status_.resolution =
          std::max<Nanos>(kHostReadResolution, *status_.latency_timer_ms * kNanosPerMilli);
      if (*status_.latency_timer_ms > 1) {
        status_.notes.push_back(fmt::format(
            "{}: USB adapter latency timer is {} ms (not writable here): gaps shorter than "
            "that are not observable; a udev rule can set it to 1",
            path, *status_.latency_timer_ms));
      }
    }
  }
}

void SerialSource::start(ChunkHandler on_chunk, ErrorHandler on_error) {
  on_chunk_ = std::move(on_chunk);
  on_error_ = std::move(on_error);
  read_next();
}

void SerialSource::close() {
  if (port_.is_open()) {
    boost::system::error_code ignored;
    port_.cancel(ignored);
    port_.close(ignored);
  }
}

std::size_t SerialSource::pending_input() {
  if (!port_.is_open()) return 0;
  int n = 0;
  if (::ioctl(port_.native_handle(), FIONREAD, &n) != 0 || n < 0) return 0;
  return static_cast<std::size_t>(n);
}

void SerialSource::discard_input() {
  if (port_.is_open()) ::tcflush(port_.native_handle(), TCIFLUSH);
  decoder_.reset();
  queued_at_open_ = false;  // those bytes are gone: the next read's came after this
}

void SerialSource::note_free_moment() {
  if (port_.is_open()) note_waiting(pending_input() > 0);
}

void SerialSource::note_quiet_until(Nanos now) {
  quiet_seen_at_ = std::max(quiet_seen_at_, now);
}

void SerialSource::note_waiting(bool input_pending) {
  late_check_.waiting(input_pending);
  if (!input_pending) note_quiet_until(clock_.now());
}

void SerialSource::read_next() {
  // Asking the driver costs a system call per read; after a read handled at once, what
  // came meanwhile has not waited long enough to matter.
  if (late_check_.handled_quickly()) {
    late_check_.waiting_after_quick_handling();
    note_quiet_until(clock_.now());
  } else {
    note_waiting(pending_input() > 0);
  }
  port_.async_read_some(asio::buffer(raw_), [this](const boost::system::error_code& error,
                                                   std::size_t n) { on_read(error, n); });
}

void SerialSource::on_read(const boost::system::error_code& error, std::size_t n) {
  // Stamp first: the time of the read completion is the time of the chunk's last byte.
  const Nanos t_end = clock_.now();
  if (error == asio::error::operation_aborted) return;
  if (error || n == 0) {
    const std::error_code ec = error ? std::error_code(error.value(), std::generic_category())
                                     : std::make_error_code(std::errc::io_error);
    close();
    if (on_error_) on_error_(ec);
    return;
  }
  bytes_.clear();
  errors_.clear();
  if (status_.error_marking) {
    decoder_.decode({raw_.data(), n}, bytes_, errors_);
  } else {
    bytes_.assign(raw_.begin(), raw_.begin() + static_cast<std::ptrdiff_t>(n));
    errors_.assign(n, kLineOk);
  }
  if (counters_) refine_with_counters(0);
  if (!bytes_.empty()) {
    bool any_error = false;
    for (const auto e : errors_) any_error = any_error || e != kLineOk;
    Chunk chunk;
    chunk.t_end = t_end;
    chunk.read_late = late_check_.read_came_late();
    if (chunk.read_late) chunk.quiet_until = std::min(quiet_seen_at_, t_end);
    if (queued_at_open_) {
      // Bytes that waited in the port before it was opened (an adapter's FIFO, a reader
      // before this one) came at times nothing tells: late by an unknown delay, as a read
      // the host made late, so no silence is measured next to them (in a rotation set,
      // none from the last byte of the recording before).
      queued_at_open_ = false;
      chunk.read_late = true;
      chunk.quiet_until = kUnknownTime;
    }
    chunk.bytes = bytes_;
    if (any_error) chunk.errors = errors_;
    chunk.origin = bytes_read_;
    bytes_read_ += bytes_.size();
    if (on_chunk_) on_chunk_(chunk);
  }
  if (port_.is_open()) read_next();
}

// In-band marks cannot tell parity from framing errors, nor a break from an error on a
// 00 byte; the driver's counters can, when exactly one kind moved during this read.
void SerialSource::refine_with_counters(std::size_t first_new) {
  int err = 0;
  const auto now = read_line_counters(port_.native_handle(), err);
  if (!now) return;
  const LineCounters before = *counters_;
  counters_ = now;
  const bool parity = now->parity > before.parity;
  const bool frame = now->frame > before.frame;
  const bool brk = now->brk > before.brk;
  for (std::size_t i = first_new; i < errors_.size(); ++i) {
    std::uint8_t& e = errors_[i];
    if (e == kBreak && !brk && (parity || frame)) e = parity ? kParityError : kFramingError;
    if ((e & (kParityError | kFramingError)) != 0) {
      if (frame && !parity) e = kFramingError;
      if (parity && !frame) e = kParityError;
    }
  }
  const bool overrun = now->overrun > before.overrun || now->buf_overrun > before.buf_overrun;
  if (overrun && !errors_.empty()) errors_.front() |= kOverrun;  // bytes were lost before it
}

}  // namespace rtu
