#include "serial/port_discovery.hpp"

#include <fcntl.h>
#include <linux/serial.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <tuple>

namespace rtu {
namespace {

namespace fs = std::filesystem;

// Opens without waiting for carrier and without becoming the controlling terminal; only
// asks the driver, reads and writes nothing.
bool opens_as_serial_port(const std::string& path, bool needs_uart) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return false;
  termios tio{};
  bool ok = ::tcgetattr(fd, &tio) == 0;
  if (ok && needs_uart) {
    serial_struct info{};
    ok = ::ioctl(fd, TIOCGSERIAL, &info) == 0 && info.type != PORT_UNKNOWN;
  }
  ::close(fd);
  return ok;
}

// Sort key of "ttyUSB10": ("ttyUSB", 10), so numbers sort as numbers.
std::tuple<std::string, unsigned long, std::string> family_key(const std::string& name) {
  std::size_t digits = name.size();
  while (digits > 0 && name[digits - 1] >= '0' && name[digits - 1] <= '9') --digits;
  const std::string number = name.substr(digits);
  return {name.substr(0, digits), number.empty() || number.size() > 9 ? 0 : std::stoul(number),
          name};
}

std::string canonical_or_empty(const fs::path& path) {
  std::error_code ec;
  auto resolved = fs::canonical(path, ec);
  return ec ? std::string() : resolved.string();
}

}  // namespace

std::vector<std::string> find_serial_ports(const std::string& dev) {
  std::vector<std::string> ports;
  std::set<std::string> devices_listed;  // canonical paths already in `ports`
  std::error_code ec;

  std::vector<std::string> by_id;
  for (const auto& entry : fs::directory_iterator(fs::path(dev) / "serial" / "by-id", ec)) {
    by_id.push_back(entry.path().string());
  }
  std::sort(by_id.begin(), by_id.end());
  for (const auto& path : by_id) {
    const std::string device = canonical_or_empty(path);
    if (device.empty() || devices_listed.contains(device)) continue;
    if (!opens_as_serial_port(path, false)) continue;
    ports.push_back(path);
    devices_listed.insert(device);
  }

  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dev, ec)) {
    const std::string name = entry.path().filename().string();
    for (const std::string_view family : {"ttyUSB", "ttyACM", "ttyS"}) {
      if (name.size() > family.size() && name.starts_with(family) &&
          std::all_of(name.begin() + static_cast<std::ptrdiff_t>(family.size()), name.end(),
                      [](char c) { return c >= '0' && c <= '9'; })) {
        names.push_back(name);
      }
    }
  }
  std::sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) {
    return family_key(a) < family_key(b);
  });
  for (const auto& name : names) {
    const std::string path = (fs::path(dev) / name).string();
    const std::string device = canonical_or_empty(path);
    if (device.empty() || devices_listed.contains(device)) continue;
    if (!opens_as_serial_port(path, name.starts_with("ttyS"))) continue;
    ports.push_back(path);
    devices_listed.insert(device);
  }
  return ports;
}

std::vector<std::string> split_port_list(std::string_view text) {
  std::vector<std::string> paths;
  while (!text.empty()) {
    const std::size_t colon = text.find(':');
    const std::string_view part = text.substr(0, colon);
    if (!part.empty()) paths.emplace_back(part);
    if (colon == std::string_view::npos) break;
    text.remove_prefix(colon + 1);
  }
  return paths;
}

}  // namespace rtu
