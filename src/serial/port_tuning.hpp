#pragma once
// Driver-level knobs of a serial port that Boost.Asio does not reach (FORMATS §7.2-7.3):
// error counters, low-latency mode, the FTDI latency timer.
#include <cstdint>
#include <optional>
#include <string>

namespace rtu {

// The error counters of TIOCGICOUNT (serial-core and usb-serial drivers; a pseudo-terminal
// has none: ENOTTY).
struct LineCounters {
  std::int64_t rx = 0;
  std::int64_t frame = 0;
  std::int64_t parity = 0;
  std::int64_t brk = 0;
  std::int64_t overrun = 0;      // UART FIFO overruns
  std::int64_t buf_overrun = 0;  // tty buffer overruns
};

// nullopt when the driver has no counters; `error` = errno then.
std::optional<LineCounters> read_line_counters(int fd, int& error);

// Sets ASYNC_LOW_LATENCY (allowed without privileges; on ftdi_sio it also sets the latency
// timer to 1 ms). Returns false with `error` = errno when the driver refuses or lacks it.
bool set_low_latency(int fd, int& error);

// The FTDI latency timer of `device_path` (ms), read from sysfs after trying to lower it
// to 1 ms when it is higher and writable. nullopt when the port is not a usb-serial device
// with that attribute. `lowered` tells whether this call changed it.
std::optional<int> tune_latency_timer(const std::string& device_path, bool& lowered);

// "ttyUSB0" for "/dev/ttyUSB0" or a symlink to it (e.g. /dev/serial/by-id/...).
std::string device_base_name(const std::string& device_path);

}  // namespace rtu
