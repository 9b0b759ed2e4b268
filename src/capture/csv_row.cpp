#include "capture/csv_row.hpp"

namespace rtu {

std::size_t CsvRow::parse(std::string_view line) {
  text_.clear();
  fields_.clear();
  line_length_ = line.size();
  std::size_t pos = 0;
  for (;;) {
    const std::size_t column = pos;
    const std::size_t offset = text_.size();
    if (pos < line.size() && line[pos] == '"') {
      ++pos;
      for (;;) {
        if (pos >= line.size()) return column;  // never closed
        if (line[pos] == '"') {
          if (pos + 1 < line.size() && line[pos + 1] == '"') {
            text_ += '"';
            pos += 2;
            continue;
          }
          ++pos;
          break;
        }
        text_ += line[pos++];
      }
      if (pos < line.size() && line[pos] != ',') return pos;
    } else {
      while (pos < line.size() && line[pos] != ',') text_ += line[pos++];
    }
    fields_.push_back({offset, text_.size() - offset, column});
    if (pos >= line.size()) return kOk;
    ++pos;  // the comma
  }
}

std::string_view CsvRow::field(std::size_t i) const {
  if (i >= fields_.size()) return {};
  return std::string_view(text_).substr(fields_[i].offset, fields_[i].length);
}

std::size_t CsvRow::column(std::size_t i) const {
  return i < fields_.size() ? fields_[i].column : line_length_;
}

}  // namespace rtu
