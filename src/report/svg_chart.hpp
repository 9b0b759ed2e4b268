#pragma once
// Tiny SVG drawing helpers for the HTML report: our own code, inline in the page, so the
// report needs nothing from the network and no script to show its charts.
#include <fmt/format.h>

#include <string>
#include <string_view>
#include <vector>

namespace rtu::svg {

// Appends `text` with &, <, >, " escaped for HTML text and attribute values.
void append_escaped(fmt::memory_buffer& out, std::string_view text);
std::string escaped(std::string_view text);

// "Nice" axis ticks covering [lo, hi]: steps of 1, 2 or 5 × 10^k, about `target` of them.
std::vector<double> nice_ticks(double lo, double hi, int target);
// A tick label without needless digits: 0.5, 12, 1500, 0.025.
std::string tick_label(double v);
// Seconds from the capture start as an axis label: "45 s", "12 min", "3.5 h".
std::string time_label(double seconds, double span_seconds);

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
// Grid lines and tick labels for both axes; x labels via `x_label(value)`.
template <typename XLabel>
void axes(fmt::memory_buffer& out, const Frame& f, const std::vector<double>& x_ticks,
          const std::vector<double>& y_ticks, XLabel&& x_label, std::string_view y_unit) {
  for (const double y : y_ticks) {
    fmt::format_to(std::back_inserter(out),
                   "<line class=\"grid\" x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\"/>"
                   "<text class=\"ylab\" x=\"{:.1f}\" y=\"{:.1f}\">{}{}</text>",
                   f.left, f.py(y), f.width - f.right, f.py(y), f.left - 4, f.py(y) + 3,
                   tick_label(y), y_unit);
  }
  for (const double x : x_ticks) {
    fmt::format_to(std::back_inserter(out),
                   "<line class=\"tick\" x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\"/>"
                   "<text class=\"xlab\" x=\"{:.1f}\" y=\"{:.1f}\">{}</text>",
                   f.px(x), f.height - f.bottom, f.px(x), f.height - f.bottom + 4, f.px(x),
                   f.height - f.bottom + 15, escaped(x_label(x)));
  }
  fmt::format_to(std::back_inserter(out),
                 "<line class=\"axis\" x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\"/>",
                 f.left, f.height - f.bottom, f.width - f.right, f.height - f.bottom);
}

}  // namespace rtu::svg
