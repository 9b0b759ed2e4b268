#include "report/prometheus_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>

namespace rtu {
namespace {

std::string_view type_name(MetricType type) {
  switch (type) {
    case MetricType::kCounter: return "counter";
    case MetricType::kGauge: return "gauge";
    case MetricType::kHistogram: return "histogram";
  }
  return "untyped";
}

bool valid_name(std::string_view name, bool colon_allowed) {
  if (name.empty()) return false;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    const bool letter =
        (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || (colon_allowed && c == ':');
    const bool digit = c >= '0' && c <= '9';
    if (!letter && !(digit && i > 0)) return false;
  }
  return true;
}

// HELP text escapes only backslash and newline; label values also the double quote.
void append_escaped(std::string& out, std::string_view text, bool quote) {
  for (const char c : text) {
    if (c == '\\') {
      out += "\\\\";
    } else if (c == '\n') {
      out += "\\n";
    } else if (quote && c == '"') {
      out += "\\\"";
    } else {
      out += c;
    }
  }
}

}  // namespace

std::string escape_label_value(std::string_view value) {
  std::string out;
  append_escaped(out, value, true);
  return out;
}

std::string format_sample_value(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
  // Counters are integers: below 2^53 they are exact in a double and read best without ".0".
  if (value == std::floor(value) && std::fabs(value) < 9007199254740992.0) {
    return fmt::format("{}", static_cast<long long>(value));
  }
  return fmt::format("{}", value);  // shortest text that reads back as the same double
}

void ExpositionWriter::family(std::string_view name, MetricType type, std::string_view help) {
  if (!valid_name(name, true)) throw std::logic_error(fmt::format("bad metric name {}", name));
  if (std::find(families_.begin(), families_.end(), name) != families_.end()) {
    throw std::logic_error(fmt::format("metric family {} declared twice", name));
  }
  families_.emplace_back(name);
  type_ = type;
  fmt::format_to(std::back_inserter(text_), "# HELP {} ", name);
  append_escaped(text_, help, false);
  fmt::format_to(std::back_inserter(text_), "\n# TYPE {} {}\n", name, type_name(type));
}

void ExpositionWriter::check_sample_name(std::string_view name) const {
  if (families_.empty()) throw std::logic_error("metric sample before any family");
  const std::string_view family = families_.back();
  if (name == family) return;
  if (type_ == MetricType::kHistogram && name.substr(0, family.size()) == family) {
    const std::string_view suffix = name.substr(family.size());
    if (suffix == "_bucket" || suffix == "_sum" || suffix == "_count") return;
  }
  throw std::logic_error(fmt::format("sample {} outside its family {}", name, family));
}

template <typename Labels>
void ExpositionWriter::write_sample(std::string_view name, const Labels& labels, double value) {
  check_sample_name(name);
  text_ += name;
  if (labels.size() != 0) {
    text_ += '{';
    bool first = true;
    for (const auto& [label, label_value] : labels) {
      if (!valid_name(label, false) || label.substr(0, 2) == "__") {
        throw std::logic_error(fmt::format("bad label name {}", label));
      }
      if (!first) text_ += ',';
      first = false;
      text_ += label;
      text_ += "=\"";
      append_escaped(text_, label_value, true);
      text_ += '"';
    }
    text_ += '}';
  }
  text_ += ' ';
  text_ += format_sample_value(value);
  text_ += '\n';
}

void ExpositionWriter::sample(std::string_view name, std::initializer_list<MetricLabel> labels,
                              double value) {
  write_sample(name, labels, value);
}

void ExpositionWriter::sample(std::string_view name, const std::vector<MetricLabel>& labels,
                              double value) {
  write_sample(name, labels, value);
}

}  // namespace rtu
