#pragma once
// Tiny SVG drawing helpers for the HTML report: our own code, inline in the page, so the
// report needs nothing from the network and no script to show its charts.
#include <fmt/format.h>

#include <string>
#include <string_view>
#include <vector>

#include "core/time.hpp"

namespace rtu::svg {

// Appends `text` with &, <, >, " escaped for HTML text and attribute values.
void append_escaped(fmt::memory_buffer& out, std::string_view text);
std::string escaped(std::string_view text);

// "Nice" axis ticks covering [lo, hi]: steps of 1, 2 or 5 × 10^k, about `target` of them.
std::vector<double> nice_ticks(double lo, double hi, int target);
// A tick label without needless digits: 0.5, 12, 1500, 0.025.
std::string tick_label(double v);

// The ticks of a time axis over [0, span] seconds from `origin` (a time on the input's
// clock). Steps come from the clock's own ladder (1-2-5 below a second, then 1, 2, 5, 10,
// 15, 30 s, 1, 2, 5, 10, 15, 30 min, 1, 2, 3, 6, 12 h, days), about `target` of them.
// On a wall clock (origin ≥ kWallClockFrom, core/time_format.hpp) ticks sit on round times of day
// and read "14:05:30" (UTC); otherwise they read the time since the start: "0", "30 s", "2 min", "1
// h 15".
struct TimeAxis {
  std::vector<double> ticks;  // seconds from origin
  std::vector<std::string> labels;
  bool wall_clock = false;
  [[nodiscard]] std::string_view caption() const;  // "time of day (UTC)", "time from start"
};
TimeAxis time_axis(Nanos origin_ns, double span, int target);

// A plot area inside an SVG element of width × height with margins for axes.
struct Frame {
  double width = 640;
  double height = 200;
  double left = 48;
  double right = 12;
  double top = 12;
  double bottom = 28;
  double x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;

  [[nodiscard]] double px(double x) const;  // data → pixel
  [[nodiscard]] double py(double y) const;
  [[nodiscard]] double plot_width() const { return width - left - right; }
  [[nodiscard]] double plot_height() const { return height - top - bottom; }
};

// <svg ...> with a viewBox, role="img" and an aria-label.
void open(fmt::memory_buffer& out, const Frame& f, std::string_view label,
          std::string_view css_class);
void close(fmt::memory_buffer& out);
// A y-axis label with the digits its tick step needs (49.98, 49.99, 50.00, not 50 and
// 50.0), large values in k or M by the largest tick (5M, 10M).
std::string axis_label(double v, double step, double largest);
// Grid lines and labels of the y axis.
void y_axis(fmt::memory_buffer& out, const Frame& f, const std::vector<double>& ticks,
            std::string_view unit);
// Tick marks, labels (one per tick) and the line of the x axis.
void x_axis(fmt::memory_buffer& out, const Frame& f, const std::vector<double>& ticks,
            const std::vector<std::string>& labels);
// Both axes; x labels via `x_label(value)`.
template <typename XLabel>
void axes(fmt::memory_buffer& out, const Frame& f, const std::vector<double>& x_ticks,
          const std::vector<double>& y_ticks, XLabel&& x_label, std::string_view y_unit) {
  y_axis(out, f, y_ticks, y_unit);
  std::vector<std::string> labels;
  labels.reserve(x_ticks.size());
  for (const double x : x_ticks) labels.push_back(x_label(x));
  x_axis(out, f, x_ticks, labels);
}

}  // namespace rtu::svg
