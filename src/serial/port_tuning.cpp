#include "serial/port_tuning.hpp"

#include <linux/serial.h>
#include <sys/ioctl.h>

#include <cerrno>
#include <filesystem>
#include <fstream>

namespace rtu {

std::optional<LineCounters> read_line_counters(int fd, int& error) {
  serial_icounter_struct ic{};
  if (::ioctl(fd, TIOCGICOUNT, &ic) != 0) {
    error = errno;
    return std::nullopt;
  }
  LineCounters c;
  c.rx = ic.rx;
  c.frame = ic.frame;
  c.parity = ic.parity;
  c.brk = ic.brk;
  c.overrun = ic.overrun;
  c.buf_overrun = ic.buf_overrun;
  return c;
}

bool set_low_latency(int fd, int& error) {
  serial_struct ss{};
  if (::ioctl(fd, TIOCGSERIAL, &ss) != 0) {
    error = errno;
    return false;
  }
  constexpr int kLowLatency = ASYNC_LOW_LATENCY;  // 1 << 13, fits an int
  if ((ss.flags & kLowLatency) != 0) return true;
  ss.flags |= kLowLatency;
  if (::ioctl(fd, TIOCSSERIAL, &ss) != 0) {
    error = errno;
    return false;
  }
  return true;
}

std::string device_base_name(const std::string& device_path) {
  std::error_code ec;
  const auto resolved = std::filesystem::canonical(device_path, ec);
  return (ec ? std::filesystem::path(device_path) : resolved).filename().string();
}

std::optional<int> tune_latency_timer(const std::string& device_path, bool& lowered) {
  lowered = false;
  const std::string attr =
      "/sys/bus/usb-serial/devices/" + device_base_name(device_path) + "/latency_timer";
  int value = 0;
  {
    std::ifstream in(attr);
    if (!in || !(in >> value)) return std::nullopt;
  }
  if (value > 1) {
    std::ofstream out(attr);
    if (out << 1 << '\n' && out.flush()) {
      out.close();
      std::ifstream again(attr);
      int now = value;
      if (again >> now && now < value) {
        lowered = true;
        value = now;
      }
    }
  }
  return value;
}

}  // namespace rtu
