#include "report/progress_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace rtu {
namespace {

// Under this, a rate is mostly start-up noise (opening, the first buffer).
constexpr double kMinSecondsForRate = 0.25;

// "0:07", "12:34", "1:02:03".
std::string clock_text(double seconds) {
  const auto total = static_cast<std::uint64_t>(std::ceil(std::max(seconds, 0.0)));
  const auto h = total / 3600;
  const auto m = (total / 60) % 60;
  const auto s = total % 60;
  if (h > 0) return fmt::format("{}:{:02}:{:02}", h, m, s);
  return fmt::format("{}:{:02}", m, s);
}

// "950", "12.3k", "4.56M": records per second vary over six orders of magnitude.
std::string count_text(double n) {
  if (n < 1e3) return fmt::format("{:.0f}", n);
  if (n < 1e6) return fmt::format("{:.1f}k", n / 1e3);
  return fmt::format("{:.2f}M", n / 1e6);
}

}  // namespace

int progress_percent(std::uint64_t bytes, std::uint64_t size) {
  if (size == 0 || bytes >= size) return 100;
  // In floating point: bytes * 100 could overflow 64 bits only past 184 PB, but the
  // division is as exact as a percentage needs.
  return static_cast<int>(static_cast<double>(bytes) * 100.0 / static_cast<double>(size));
}

std::string progress_text(const ProgressFigures& f) {
  const int percent = progress_percent(f.bytes, f.size);
  std::string rate = "-- MB/s  -- rec/s";
  std::string eta = "--:--";
  if (f.seconds >= kMinSecondsForRate && f.bytes > 0) {
    const double bytes_per_second = static_cast<double>(f.bytes) / f.seconds;
    rate = fmt::format("{:.1f} MB/s  {} rec/s", bytes_per_second / 1e6,
                       count_text(static_cast<double>(f.records) / f.seconds));
    const std::uint64_t left = f.size > f.bytes ? f.size - f.bytes : 0;
    eta = clock_text(static_cast<double>(left) / bytes_per_second);
  }
  return fmt::format("{}  {:3}%  {}  ETA {}", f.label, percent, rate, eta);
}

}  // namespace rtu
