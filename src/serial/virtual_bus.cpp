#include "serial/virtual_bus.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <pthread.h>
#include <pty.h>
#include <sched.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <system_error>

#include "core/chunk.hpp"
#include "core/input_error.hpp"
#include "core/thread_name.hpp"
#include "serial/custom_baud.hpp"

namespace rtu {
namespace {

Nanos monotonic_now() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<Nanos>(ts.tv_sec) * kNanosPerSecond + ts.tv_nsec;
}

[[noreturn]] void throw_errno(const std::string& what) {
  throw std::system_error(errno, std::generic_category(), what);
}

LineSettings settings_of_pty(int master, const LineSettings& fallback) {
  termios tio{};
  if (::tcgetattr(master, &tio) != 0) return fallback;
  LineSettings s;
  s.baud = read_baud(master).value_or(0);
  if (s.baud == 0) s.baud = fallback.baud;
  const bool two = (tio.c_cflag & CSTOPB) != 0;
  const bool odd = (tio.c_cflag & PARODD) != 0;
  s.stop_bits = two ? 2 : 1;
  if ((tio.c_cflag & PARENB) != 0) {
    s.parity = odd ? Parity::kOdd : Parity::kEven;
  } else {
    // drivers/tty/pty.c clears PARENB on every change: see EndpointUart.
    s.parity = odd ? Parity::kOdd : (two ? Parity::kNone : Parity::kEven);
  }
  return s;
}

bool same_line(const LineSettings& a, const LineSettings& b) {
  return a.baud == b.baud && a.parity == b.parity && a.stop_bits == b.stop_bits;
}

}  // namespace

struct VirtualBus::Endpoint {
  int master = -1;
  int slave = -1;  // held open so the master never sees a hang-up between users
  std::string pts;
  std::string link;
  bool usb = false;
  std::vector<std::uint8_t> usb_buffer;
  Nanos usb_deadline = 0;
  std::vector<std::uint8_t> out;  // bytes to write in this round
  Nanos out_oldest_end = 0;       // wire end of out's first byte
  // Emulated UARTs only.
  std::optional<UartReceiver> receiver;
  bool marks = false;  // the program asked for PARMRK (which the bus cleared)
  bool termios_seen = false;
  termios last_termios{};  // as the bus last saw (or left) it
  std::vector<ReceivedChar> received;
};

VirtualBus::VirtualBus(VirtualBusOptions options)
    : options_(std::move(options)), rng_state_(options_.seed == 0 ? 1 : options_.seed) {
  running_ = true;  // until stop(): run() returns at once after it
  char_time_ = options_.line.char_time();
  origin_ = monotonic_now();
  line_ = LineLevels(!options_.invert);
  endpoints_.resize(options_.endpoints);
  for (const auto i : options_.usb_endpoints) {
    if (i < endpoints_.size()) endpoints_[i].usb = true;
  }
  if (!options_.link_dir.empty()) std::filesystem::create_directories(options_.link_dir);
  for (std::size_t i = 0; i < endpoints_.size(); ++i) {
    open_endpoint(i);
    paths_.push_back(endpoints_[i].link.empty() ? endpoints_[i].pts : endpoints_[i].link);
  }
  if (::pipe2(wake_pipe_, O_NONBLOCK | O_CLOEXEC) != 0) throw_errno("pipe");
  if (!options_.log_path.empty()) {
    log_file_ = std::fopen(options_.log_path.c_str(), "w");
    if (log_file_ == nullptr) throw_errno(options_.log_path);
    fmt::print(log_file_,
               "# virtual bus log: one line per read from a writer, wire end time (monotonic s)\n");
    fmt::print(log_file_, "# baud={} parity={} stop={}\n", options_.line.baud,
               parity_letter(options_.line.parity), options_.line.stop_bits);
    std::fflush(log_file_);
  }
}

VirtualBus::~VirtualBus() {
  stop();
  for (std::size_t i = 0; i < endpoints_.size(); ++i) close_endpoint(i);
  for (const int fd : wake_pipe_) {
    if (fd >= 0) ::close(fd);
  }
  if (log_file_ != nullptr) std::fclose(log_file_);
}

void VirtualBus::open_endpoint(std::size_t index) {
  Endpoint& ep = endpoints_[index];
  char name[256] = {};
  if (::openpty(&ep.master, &ep.slave, name, nullptr, nullptr) != 0) throw_errno("openpty");
  ep.pts = name;
  ::fcntl(ep.master, F_SETFL, ::fcntl(ep.master, F_GETFL) | O_NONBLOCK);
  ::fcntl(ep.master, F_SETFD, FD_CLOEXEC);
  ::fcntl(ep.slave, F_SETFD, FD_CLOEXEC);
  // Raw, so nothing is echoed back onto the bus before a program configures the port.
  // The speed stays at the pty default, so a program's own settings always change
  // something (a tcsetattr that only changes PARENB fails with EINVAL on a pty).
  termios tio{};
  ::tcgetattr(ep.slave, &tio);
  ::cfmakeraw(&tio);
  ::tcsetattr(ep.slave, TCSANOW, &tio);
  ep.termios_seen = false;
  ep.marks = false;
  ep.receiver.reset();
  if (!options_.link_dir.empty()) {
    ep.link = (std::filesystem::path(options_.link_dir) / fmt::format("ep{}", index)).string();
    std::error_code ec;
    std::filesystem::remove(ep.link, ec);
    std::filesystem::create_symlink(ep.pts, ep.link);
  }
}

void VirtualBus::close_endpoint(std::size_t index) {
  Endpoint& ep = endpoints_[index];
  if (ep.master >= 0) ::close(ep.master);
  if (ep.slave >= 0) ::close(ep.slave);
  ep.master = -1;
  ep.slave = -1;
  ep.usb_buffer.clear();
  ep.out.clear();
}

void VirtualBus::unplug(std::size_t endpoint) {
  {
    const std::lock_guard lock(mutex_);
    close_endpoint(endpoint);
    if (!endpoints_[endpoint].link.empty()) {
      std::error_code ec;
      std::filesystem::remove(endpoints_[endpoint].link, ec);
    }
  }
  const char c = 'u';
  [[maybe_unused]] const auto n = ::write(wake_pipe_[1], &c, 1);
}

void VirtualBus::replug(std::size_t endpoint) {
  {
    const std::lock_guard lock(mutex_);
    if (endpoints_[endpoint].master < 0) open_endpoint(endpoint);
  }
  const char c = 'r';
  [[maybe_unused]] const auto n = ::write(wake_pipe_[1], &c, 1);
}

void VirtualBus::start() {
  thread_ = std::thread([this] {
    name_this_thread("rtu-virtual-bus");
    run();
  });
}

void VirtualBus::stop() {
  running_ = false;
  if (wake_pipe_[1] >= 0) {
    const char c = 's';
    [[maybe_unused]] const auto n = ::write(wake_pipe_[1], &c, 1);
  }
  if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
}

std::vector<BusLogEntry> VirtualBus::log() const {
  const std::lock_guard lock(mutex_);
  return log_;
}

void VirtualBus::run() {
  // Pacing is only as good as this thread's wake-ups: ask for real-time scheduling where
  // allowed (root or CAP_SYS_NICE); otherwise stay as we are.
  sched_param param{};
  param.sched_priority = 10;
  ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &param);
  std::vector<pollfd> fds;
  std::vector<std::size_t> owners;
  while (running_) {
    Nanos next_due = -1;
    {
      const std::lock_guard lock(mutex_);
      fds.clear();
      owners.clear();
      fds.push_back({wake_pipe_[0], POLLIN, 0});
      owners.push_back(endpoints_.size());
      for (std::size_t i = 0; i < endpoints_.size(); ++i) {
        if (endpoints_[i].master < 0) continue;
        fds.push_back({endpoints_[i].master, POLLIN, 0});
        owners.push_back(i);
        if (!endpoints_[i].usb_buffer.empty()) {
          const Nanos d = endpoints_[i].usb_deadline;
          next_due = next_due < 0 ? d : std::min(next_due, d);
        }
      }
      if (queue_head_ < queue_.size()) {
        const Nanos d = queue_[queue_head_].t_end;
        next_due = next_due < 0 ? d : std::min(next_due, d);
      }
      if (uart_wake_ >= 0) next_due = next_due < 0 ? uart_wake_ : std::min(next_due, uart_wake_);
    }
    timespec timeout{};
    timespec* timeout_ptr = nullptr;
    if (next_due >= 0) {
      const Nanos wait = std::max<Nanos>(0, next_due - monotonic_now());
      timeout.tv_sec = static_cast<time_t>(wait / kNanosPerSecond);
      timeout.tv_nsec = static_cast<long>(wait % kNanosPerSecond);
      timeout_ptr = &timeout;
    }
    const int ready = ::ppoll(fds.data(), fds.size(), timeout_ptr, nullptr);
    if (ready < 0 && errno != EINTR) throw_errno("ppoll");
    const std::lock_guard lock(mutex_);
    const Nanos now = monotonic_now();
    if (ready > 0) {
      if ((fds[0].revents & POLLIN) != 0) {
        char drain[64];
        while (::read(wake_pipe_[0], drain, sizeof drain) > 0) {
        }
      }
      for (std::size_t k = 1; k < fds.size(); ++k) {
        const std::size_t i = owners[k];
        if (endpoints_[i].master != fds[k].fd) continue;  // unplugged meanwhile
        if ((fds[k].revents & POLLIN) != 0) read_from(i, now);
      }
    }
    deliver_due(now);
  }
}

void VirtualBus::read_from(std::size_t index, Nanos now) {
  std::uint8_t buffer[4096];
  const ssize_t n = ::read(endpoints_[index].master, buffer, sizeof buffer);
  if (n <= 0) return;
  const bool uart = emulating();
  const LineSettings tx = uart ? uart_of(index, true) : options_.line;
  const Nanos char_time = uart ? tx.char_time() : char_time_;
  // Consecutive bytes of one writer while the line is still busy with its previous byte
  // belong to the same burst.
  const bool continues = !log_.empty() && log_.back().from == index && line_free_at_ >= now;
  Nanos t = std::max(now, line_free_at_);
  if (uart && !continues) t = render_burst_start(index, t, tx);
  if (!continues) log_.push_back(BusLogEntry{index, t, t, {}});
  BusLogEntry& entry = log_.back();
  const Nanos last = t + char_time * static_cast<Nanos>(n);
  const Picos drawn_from = std::max(to_picos(t), line_end_);
  for (ssize_t k = 0; k < n; ++k) {
    if (uart) {
      line_end_ =
          render_char(line_, std::max(to_picos(t), line_end_), buffer[k], tx, options_.invert);
    }
    t += char_time;
    queue_.push_back(Pending{options_.per_byte ? t : last, index, buffer[k]});
    entry.bytes.push_back(buffer[k]);
  }
  if (uart) bursts_.push_back(Burst{index, drawn_from, line_end_});
  entry.t_end = t;
  line_free_at_ = t;
  if (log_file_ != nullptr) {
    // One line per read: a text hex capture whose times are the wire end of each read.
    fmt::memory_buffer line;
    const Nanos start = t - char_time * static_cast<Nanos>(n);
    fmt::format_to(std::back_inserter(line), "# from ep{} start {}.{:09}\n{}.{:09} ", index,
                   start / kNanosPerSecond, start % kNanosPerSecond, t / kNanosPerSecond,
                   t % kNanosPerSecond);
    for (ssize_t k = 0; k < n; ++k) fmt::format_to(std::back_inserter(line), "{:02x}", buffer[k]);
    line.push_back('\n');
    std::fwrite(line.data(), 1, line.size(), log_file_);
    std::fflush(log_file_);
  }
}

bool VirtualBus::emulating() const {
  return !options_.listen_as.empty() || !options_.talk_as.empty() || options_.invert ||
         options_.bias_glitches;
}

LineSettings VirtualBus::uart_of(std::size_t index, bool transmit) const {
  const auto& table = transmit ? options_.talk_as : options_.listen_as;
  const auto it = table.find(index);
  if (it == table.end()) return options_.line;
  if (!it->second.follow_pty) return it->second.line;
  return settings_of_pty(endpoints_[index].master, options_.line);
}

// A driver that takes the line after another has let go of it: on an unbiased pair the
// released line floats and the driver's enable shows as a short low pulse, one bit at the
// new writer's rate, well before its first character.
Nanos VirtualBus::render_burst_start(std::size_t writer, Nanos t, const LineSettings& tx) {
  const bool turnaround = writer != last_writer_;
  last_writer_ = writer;
  if (!options_.bias_glitches || !turnaround) return t;
  const Picos pulse = std::max(to_picos(t), line_end_);
  line_.set(pulse, options_.invert);
  line_.set(pulse + half_bits_at(tx.baud, 2), !options_.invert);
  line_end_ = pulse + half_bits_at(tx.baud, 2);
  return t + 2 * tx.char_time();
}

void VirtualBus::deliver_due(Nanos now) {
  if (emulating()) {
    // The line is final up to now; without per-byte delivery it is handed on only up to
    // the end of the last whole read, as the plain relay does.
    std::optional<Nanos> due_end;
    while (queue_head_ < queue_.size() && queue_[queue_head_].t_end <= now) {
      due_end = queue_[queue_head_++].t_end;
    }
    const bool more = queue_head_ < queue_.size();
    if (!more) {
      queue_.clear();
      queue_head_ = 0;
    }
    deliver_emulated(now, more ? due_end : std::optional<Nanos>(now));
    return;
  }
  while (queue_head_ < queue_.size() && queue_[queue_head_].t_end <= now) {
    const Pending& p = queue_[queue_head_++];
    for (std::size_t j = 0; j < endpoints_.size(); ++j) {
      if (j == p.from || endpoints_[j].master < 0) continue;
      const std::uint8_t byte = maybe_flip(p.byte, j);
      Endpoint& ep = endpoints_[j];
      if (ep.usb) {
        if (ep.usb_buffer.empty()) ep.usb_deadline = now + options_.usb_latency;
        ep.usb_buffer.push_back(byte);
        if (ep.usb_buffer.size() >= options_.usb_packet) flush_usb(j, now, true);
      } else {
        if (ep.out.empty()) ep.out_oldest_end = p.t_end;
        ep.out.push_back(byte);
      }
    }
  }
  if (queue_head_ == queue_.size()) {
    queue_.clear();
    queue_head_ = 0;
  }
  for (std::size_t j = 0; j < endpoints_.size(); ++j) {
    Endpoint& ep = endpoints_[j];
    if (ep.usb) flush_usb(j, now, false);
    if (!ep.out.empty()) {
      log_late_delivery(j, ep.out_oldest_end, now);
      write_to(j, ep.out.data(), ep.out.size());
      ep.out.clear();
    }
  }
}

// The bus's own thread woke late (a loaded machine): the endpoint sees a pause the wire
// never had. Logged, so a test tells the bus's lateness from the reader's.
void VirtualBus::log_late_delivery(std::size_t to, Nanos wire_end, Nanos now) {
  if (log_file_ == nullptr || now - wire_end < kLateDeliveryLogged) return;
  fmt::print(log_file_, "# late to ep{}: byte ending {}.{:09} delivered at {}.{:09}\n", to,
             wire_end / kNanosPerSecond, wire_end % kNanosPerSecond, now / kNanosPerSecond,
             now % kNanosPerSecond);
  std::fflush(log_file_);
}

std::uint8_t VirtualBus::maybe_flip(std::uint8_t byte, std::size_t to) {
  if (options_.flip_probability <= 0.0) return byte;
  rng_state_ = rng_state_ * 6364136223846793005ULL + 1442695040888963407ULL;
  const double u = static_cast<double>(rng_state_ >> 11U) / 9007199254740992.0;
  if (u >= options_.flip_probability) return byte;
  const auto flipped = static_cast<std::uint8_t>(byte ^ (1U << ((rng_state_ >> 5U) & 7U)));
  ++flipped_;
  if (log_file_ != nullptr) {
    fmt::print(log_file_, "# fault: byte {:02x} delivered to ep{} as {:02x}\n", byte, to, flipped);
  }
  return flipped;
}

void VirtualBus::deliver_emulated(Nanos now, std::optional<Nanos> line_known_until) {
  if (line_known_until) line_known_ = std::max(line_known_, to_picos(*line_known_until));
  uart_wake_ = -1;
  Picos oldest_needed = line_known_;
  for (std::size_t j = 0; j < endpoints_.size(); ++j) {
    Endpoint& ep = endpoints_[j];
    if (ep.master < 0) continue;
    receive_at(j, line_known_);
    if (ep.receiver) {
      oldest_needed = std::min(oldest_needed, ep.receiver->resume_point());
      // A character begun before the end of the line known so far: wake when it is whole
      // (later characters are waited for by the reads still queued).
      const auto whole = ep.receiver->next_complete(line_);
      if (whole && *whole > line_known_ && queue_head_ == queue_.size()) {
        const Nanos wake = to_nanos(*whole);
        uart_wake_ = uart_wake_ < 0 ? wake : std::min(uart_wake_, wake);
      }
    }
    if (ep.usb) flush_usb(j, now, false);
    if (!ep.out.empty()) {
      write_to(j, ep.out.data(), ep.out.size());
      ep.out.clear();
    }
  }
  line_.forget_before(oldest_needed);
  while (!bursts_.empty() && bursts_.front().end < oldest_needed) bursts_.pop_front();
}

void VirtualBus::receive_at(std::size_t index, Picos known_until) {
  Endpoint& ep = endpoints_[index];
  const LineSettings rx = uart_of(index, false);
  if (!ep.receiver) {
    ep.receiver.emplace(rx, known_until);  // a new port hears nothing from before it
  } else if (!same_line(ep.receiver->settings(), rx)) {
    ep.receiver->reconfigure(rx, known_until);
  }
  // PARMRK: the program wants error marks; the kernel would double every FF itself and
  // has no way to mark errors on a pty, so the bus takes the flag off and marks instead.
  termios tio{};
  if (::tcgetattr(ep.master, &tio) == 0) {
    const bool changed = !ep.termios_seen || tio.c_iflag != ep.last_termios.c_iflag ||
                         tio.c_cflag != ep.last_termios.c_cflag ||
                         tio.c_lflag != ep.last_termios.c_lflag;
    if ((tio.c_iflag & PARMRK) != 0) {
      tio.c_iflag &= ~static_cast<tcflag_t>(PARMRK);
      ::tcsetattr(ep.master, TCSANOW, &tio);
      ep.marks = true;
    } else if (changed) {
      ep.marks = false;  // the program set its port again, without PARMRK
    }
    ep.last_termios = tio;
    ep.termios_seen = true;
  }
  ep.received.clear();
  ep.receiver->receive(line_, known_until, ep.received);
  for (const auto& c : ep.received) {
    bool own = false;
    for (const auto& b : bursts_)
      own = own || (b.from == index && c.start >= b.start && c.start < b.end);
    if (!own) put_received(index, c);
  }
}

// What read() returns for one character, as n_tty gives it (FORMATS §7.1).
void VirtualBus::put_received(std::size_t index, const ReceivedChar& c) {
  Endpoint& ep = endpoints_[index];
  std::vector<std::uint8_t> bytes;
  const tcflag_t iflag = ep.last_termios.c_iflag;
  if (c.error == kLineOk) {
    const std::uint8_t b = maybe_flip(c.byte, index);
    bytes.push_back(b);
    if (ep.marks && b == 0xFF) bytes.push_back(0xFF);
  } else if (c.error == kBreak) {
    if ((iflag & IGNBRK) != 0) return;
    if (ep.marks) bytes = {0xFF, 0x00};
    bytes.push_back(0x00);
  } else if ((iflag & INPCK) == 0) {
    bytes.push_back(c.byte);
    if (ep.marks && c.byte == 0xFF) bytes.push_back(0xFF);
  } else {
    if ((iflag & IGNPAR) != 0) return;
    if (ep.marks) {
      bytes = {0xFF, 0x00, c.byte};
    } else {
      bytes.push_back(0x00);
    }
  }
  if (ep.usb) {
    if (ep.usb_buffer.empty()) ep.usb_deadline = to_nanos(c.end) + options_.usb_latency;
    ep.usb_buffer.insert(ep.usb_buffer.end(), bytes.begin(), bytes.end());
    if (ep.usb_buffer.size() >= options_.usb_packet) flush_usb(index, to_nanos(c.end), true);
  } else {
    ep.out.insert(ep.out.end(), bytes.begin(), bytes.end());
  }
}

void VirtualBus::flush_usb(std::size_t index, Nanos now, bool force) {
  Endpoint& ep = endpoints_[index];
  if (ep.usb_buffer.empty() || (!force && now < ep.usb_deadline)) return;
  write_to(index, ep.usb_buffer.data(), ep.usb_buffer.size());
  ep.usb_buffer.clear();
}

void VirtualBus::write_to(std::size_t index, const std::uint8_t* data, std::size_t n) {
  const int fd = endpoints_[index].master;
  while (n > 0) {
    const ssize_t w = ::write(fd, data, n);
    if (w <= 0) {
      if (w < 0 && errno == EINTR) continue;
      dropped_ += n;  // nobody reads this endpoint and its buffer is full
      return;
    }
    data += w;
    n -= static_cast<std::size_t>(w);
  }
}

int open_bus_endpoint(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) throw InputError(fmt::format("{}: cannot open the virtual bus endpoint", path));
  termios tio{};
  ::tcgetattr(fd, &tio);
  ::cfmakeraw(&tio);
  ::cfsetspeed(&tio, B9600);  // a pty carries bytes at any speed; the bus does the pacing
  ::tcsetattr(fd, TCSANOW, &tio);
  return fd;
}

}  // namespace rtu
