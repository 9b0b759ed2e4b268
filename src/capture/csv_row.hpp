#pragma once
// One CSV row (RFC 4180 quoting: fields in double quotes may hold commas, "" is a quote),
// split into fields that remember their column for error messages. A row never spans lines.
// The storage is reused from row to row, so after warm-up parsing allocates nothing.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace rtu {

class CsvRow {
 public:
  static constexpr std::size_t kOk = static_cast<std::size_t>(-1);

  // Splits `line`. Returns kOk, or the 0-based column of a quote that is not closed, or of
  // text after a closing quote (`"ab"c`).
  std::size_t parse(std::string_view line);

  [[nodiscard]] std::size_t size() const { return fields_.size(); }
  // Field `i` unquoted; empty for a missing field (i ≥ size()).
  [[nodiscard]] std::string_view field(std::size_t i) const;
  // 0-based column of field `i` in the line; the end of the line for a missing field.
  [[nodiscard]] std::size_t column(std::size_t i) const;

 private:
  struct Field {
    std::size_t offset;  // in text_
    std::size_t length;
    std::size_t column;
  };
  std::string text_;  // unquoted fields back to back
  std::vector<Field> fields_;
  std::size_t line_length_ = 0;
};

}  // namespace rtu
