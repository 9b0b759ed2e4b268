#pragma once
// Writes Prometheus' text exposition format, version 0.0.4 (FORMATS §11.1): one HELP and one
// TYPE line per family before its samples, label values escaped, numbers in the format's
// spelling (+Inf, -Inf, NaN). The writer only spells; which series exist and that a family's
// samples stay together is the caller's business, checked here where it is cheap: a family
// declared twice, or a sample outside the family declared last, is a programming error
// (std::logic_error), never a silently wrong scrape.
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace rtu {

enum class MetricType { kCounter, kGauge, kHistogram };

// A label: name and value. Names must match [a-zA-Z_][a-zA-Z0-9_]*; values are any UTF-8.
using MetricLabel = std::pair<std::string_view, std::string_view>;

class ExpositionWriter {
 public:
  // The Content-Type header of what this writes.
  static constexpr std::string_view kContentType = "text/plain; version=0.0.4; charset=utf-8";

  // Starts the family `name`: its HELP (escaped) and TYPE lines.
  void family(std::string_view name, MetricType type, std::string_view help);
  // One sample of the current family: `name` is the family's name, or for a histogram the
  // family's name plus `_bucket`, `_sum` or `_count`.
  void sample(std::string_view name, std::initializer_list<MetricLabel> labels, double value);
  void sample(std::string_view name, const std::vector<MetricLabel>& labels, double value);

  // The text so far; every line ends with '\n', as the format requires of the last one.
  [[nodiscard]] const std::string& text() const { return text_; }

 private:
  void check_sample_name(std::string_view name) const;
  template <typename Labels>
  void write_sample(std::string_view name, const Labels& labels, double value);

  std::string text_;
  std::vector<std::string> families_;
  MetricType type_ = MetricType::kGauge;
};

// A label value escaped for the format: backslash, double quote and newline.
std::string escape_label_value(std::string_view value);
// A sample value in the format's spelling: integers without a fraction, +Inf, -Inf, NaN.
std::string format_sample_value(double value);

}  // namespace rtu
