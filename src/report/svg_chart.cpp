#include "report/svg_chart.hpp"

#include <algorithm>
#include <cmath>

#include "core/time_format.hpp"

namespace rtu::svg {

void append_escaped(fmt::memory_buffer& out, std::string_view text) {
  for (const char c : text) {
    switch (c) {
      case '&': out.append(std::string_view("&amp;")); break;
      case '<': out.append(std::string_view("&lt;")); break;
      case '>': out.append(std::string_view("&gt;")); break;
      case '"': out.append(std::string_view("&quot;")); break;
      default: out.push_back(c);
    }
  }
}

std::string escaped(std::string_view text) {
  fmt::memory_buffer b;
  append_escaped(b, text);
  return fmt::to_string(b);
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!(hi > lo) || target < 1) {
    ticks.push_back(lo);
    return ticks;
  }
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (const double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * mag;
    if (step >= raw) break;
  }
  const double first = std::ceil(lo / step - 1e-9) * step;
  for (double v = first; v <= hi + step * 1e-9; v += step) {
    ticks.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
    if (ticks.size() > 50) break;
  }
  return ticks;
}

std::string tick_label(double v) {
  if (v == 0.0) return "0";
  const double a = std::abs(v);
  if (a >= 100 || a == std::round(a)) return fmt::format("{:.0f}", v);
  if (a >= 1) return fmt::format("{:.1f}", v);
  if (a >= 0.01) return fmt::format("{:.2f}", v);
  return fmt::format("{:.3g}", v);
}

namespace {

constexpr Nanos kNs = kNanosPerSecond;
constexpr Nanos kDay = 86'400 * kNs;

// Steps of a time axis in nanoseconds: 1-2-5 from a microsecond to half a second, then the
// clock's own divisions, then days in 1-2-5 (whole days, so labels stay dates).
Nanos time_step(double raw_seconds) {
  static constexpr Nanos kClock[] = {1 * kNs,     2 * kNs,    5 * kNs,    10 * kNs,   15 * kNs,
                                     30 * kNs,    60 * kNs,   120 * kNs,  300 * kNs,  600 * kNs,
                                     900 * kNs,   1800 * kNs, 3600 * kNs, 7200 * kNs, 10800 * kNs,
                                     21600 * kNs, 43200 * kNs};
  const double raw = raw_seconds * 1e9;
  for (Nanos step = 1000; step < kNs; step *= 10) {
    for (const Nanos m : {1, 2, 5}) {
      if (static_cast<double>(step * m) >= raw) return step * m;
    }
  }
  for (const Nanos step : kClock) {
    if (static_cast<double>(step) >= raw) return step;
  }
  for (Nanos days = 1;; days *= 10) {
    for (const Nanos m : {1, 2, 5}) {
      if (static_cast<double>(days * m * kDay) >= raw || days > 100'000) return days * m * kDay;
    }
  }
}

// Digits after the point that a step of `step` ns needs when shown in seconds.
int step_decimals(Nanos step) {
  int d = 0;
  for (Nanos unit = kNs; step % unit != 0 && d < 6; unit /= 10) ++d;
  return d;
}

Nanos floor_div(Nanos a, Nanos b) {
  return a / b - ((a % b != 0) && ((a < 0) != (b < 0)) ? 1 : 0);
}

// A tick on a wall clock: a date for day steps, "14:05" for minute steps, else "14:05:30"
// with the decimals the step needs.
std::string time_of_day(Nanos t, Nanos step) {
  fmt::memory_buffer out;
  if (step >= kDay) {
    append_utc_date(out, t);
  } else {
    append_utc_time_of_day(out, t, step_decimals(step));
    if (step >= 60 * kNs) out.resize(5);  // "14:05"
  }
  return fmt::to_string(out);
}

std::string since_start(Nanos t, Nanos step) {
  if (t == 0) return "0";
  if (step < 60 * kNs) {
    return fmt::format("{:.{}f} s", static_cast<double>(t) / 1e9, step_decimals(step));
  }
  const Nanos minutes = t / (60 * kNs);
  if (step >= kDay) return fmt::format("{} d", t / kDay);
  if (minutes < 60) return fmt::format("{} min", minutes);
  if (minutes % 60 == 0) return fmt::format("{} h", minutes / 60);
  return fmt::format("{} h {:02d}", minutes / 60, minutes % 60);
}

}  // namespace

std::string_view TimeAxis::caption() const {
  return wall_clock ? "time of day (UTC)" : "time from the start";
}

TimeAxis time_axis(Nanos origin_ns, double span, int target) {
  TimeAxis axis;
  axis.wall_clock = origin_ns >= kWallClockFrom;
  if (!(span > 0) || target < 1) {
    axis.ticks.push_back(0);
    axis.labels.push_back(axis.wall_clock ? time_of_day(origin_ns, kNs) : "0");
    return axis;
  }
  const Nanos step = time_step(span / target);
  const auto span_ns = static_cast<Nanos>(span * 1e9);
  // On a wall clock the first tick is the first round time at or after the origin.
  Nanos t = axis.wall_clock ? (floor_div(origin_ns - 1, step) + 1) * step - origin_ns : 0;
  for (; t <= span_ns && axis.ticks.size() < 60; t += step) {
    axis.ticks.push_back(static_cast<double>(t) / 1e9);
    axis.labels.push_back(axis.wall_clock ? time_of_day(origin_ns + t, step)
                                          : since_start(t, step));
  }
  return axis;
}

std::string axis_label(double v, double step, double largest) {
  if (v == 0.0) return "0";
  double div = 1.0;
  std::string_view suffix;
  if (largest >= 1e6) {
    div = 1e6;
    suffix = "M";
  } else if (largest >= 1e4) {
    div = 1e3;
    suffix = "k";
  }
  const double s = step / div;
  int decimals = 0;
  if (s > 0.0 && s < 1.0) decimals = static_cast<int>(std::ceil(-std::log10(s) - 1e-9));
  return fmt::format("{:.{}f}{}", v / div, std::clamp(decimals, 0, 9), suffix);
}

void y_axis(fmt::memory_buffer& out, const Frame& f, const std::vector<double>& ticks,
            std::string_view unit) {
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : 0.0;
  double largest = 0.0;
  for (const double y : ticks) largest = std::max(largest, std::abs(y));
  for (const double y : ticks) {
    fmt::format_to(std::back_inserter(out),
                   "<line class=\"grid\" x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\"/>"
                   "<text class=\"ylab\" x=\"{:.1f}\" y=\"{:.1f}\">{}{}</text>",
                   f.left, f.py(y), f.width - f.right, f.py(y), f.left - 4, f.py(y) + 3,
                   axis_label(y, step, largest), unit);
  }
}

void x_axis(fmt::memory_buffer& out, const Frame& f, const std::vector<double>& ticks,
            const std::vector<std::string>& labels) {
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    const double x = f.px(ticks[i]);
    fmt::format_to(std::back_inserter(out),
                   "<line class=\"tick\" x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\"/>"
                   "<text class=\"xlab\" x=\"{:.1f}\" y=\"{:.1f}\">",
                   x, f.height - f.bottom, x, f.height - f.bottom + 4, x, f.height - f.bottom + 15);
    if (i < labels.size()) append_escaped(out, labels[i]);
    out.append(std::string_view("</text>"));
  }
  fmt::format_to(std::back_inserter(out),
                 "<line class=\"axis\" x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\"/>",
                 f.left, f.height - f.bottom, f.width - f.right, f.height - f.bottom);
}

double Frame::px(double x) const {
  const double span = x_hi > x_lo ? x_hi - x_lo : 1.0;
  return left + (x - x_lo) / span * plot_width();
}

double Frame::py(double y) const {
  const double span = y_hi > y_lo ? y_hi - y_lo : 1.0;
  return top + plot_height() - (y - y_lo) / span * plot_height();
}

void open(fmt::memory_buffer& out, const Frame& f, std::string_view label,
          std::string_view css_class) {
  fmt::format_to(std::back_inserter(out),
                 "<svg class=\"{}\" viewBox=\"0 0 {:.0f} {:.0f}\" width=\"{:.0f}\" "
                 "height=\"{:.0f}\" role=\"img\" aria-label=\"",
                 css_class, f.width, f.height, f.width, f.height);
  append_escaped(out, label);
  out.append(std::string_view("\">"));
}

void close(fmt::memory_buffer& out) {
  out.append(std::string_view("</svg>"));
}

}  // namespace rtu::svg
