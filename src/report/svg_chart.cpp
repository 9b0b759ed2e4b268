#include "report/svg_chart.hpp"

#include <cmath>

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

std::string time_label(double seconds, double span_seconds) {
  if (span_seconds >= 3 * 3600) return tick_label(seconds / 3600.0) + " h";
  if (span_seconds >= 180) return tick_label(seconds / 60.0) + " min";
  return tick_label(seconds) + " s";
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
