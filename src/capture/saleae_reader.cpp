#include "capture/saleae_reader.hpp"

#include <fmt/format.h>

#include <limits>
#include <utility>

#include "capture/decimal_time.hpp"
#include "capture/found_text.hpp"
#include "core/hex_digits.hpp"
#include "core/input_error.hpp"

namespace rtu {
namespace {

constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
constexpr std::string_view kLegacyHeader = "Time [s],Value,Parity Error,Framing Error";
constexpr std::string_view kDataTableHeader = "name,type,start_time,duration,\"data\"";

char lower(char c) {
  return c >= 'A' && c <= 'Z' ? static_cast<char>(c + ('a' - 'A')) : c;
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (lower(a[i]) != lower(b[i])) return false;
  }
  return true;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::string_view strip_bom(std::string_view line) {
  if (line.substr(0, kByteOrderMark.size()) == kByteOrderMark)
    line.remove_prefix(kByteOrderMark.size());
  return line;
}

std::size_t find_column(const CsvRow& header, std::string_view name) {
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (iequals(trim(header.field(i)), name)) return i;
  }
  return static_cast<std::size_t>(-1);
}

bool has_column(const CsvRow& header, std::string_view name) {
  return find_column(header, name) != static_cast<std::size_t>(-1);
}

SaleaeLayout classify(const CsvRow& header) {
  if (has_column(header, "Time [s]")) {
    if (has_column(header, "Value")) return SaleaeLayout::kLegacy;
    if (has_column(header, "Packet ID") || has_column(header, "Address") ||
        has_column(header, "Data")) {
      return SaleaeLayout::kLegacyMultiProcessor;
    }
    return SaleaeLayout::kNone;
  }
  if (has_column(header, "start_time") && has_column(header, "type")) {
    return has_column(header, "address") ? SaleaeLayout::kDataTableMultiProcessor
                                         : SaleaeLayout::kDataTable;
  }
  return SaleaeLayout::kNone;
}

}  // namespace

SaleaeLayout recognise_saleae_header(std::string_view first_line) {
  CsvRow header;
  if (header.parse(strip_bom(first_line)) != CsvRow::kOk) return SaleaeLayout::kNone;
  return classify(header);
}

SaleaeReader::SaleaeReader(const CaptureFile& file, WarningSink warnings)
    : lines_(file), clamp_(file.name, std::move(warnings)) {
  read_header();
}

void SaleaeReader::fail(std::size_t column0, std::string_view what) const {
  throw InputError(
      fmt::format("{}:{}:{}: {}", lines_.name(), lines_.line_number(), column0 + 1, what));
}

void SaleaeReader::fail_field(std::size_t index, std::string_view expected) const {
  fail(row_.column(index), fmt::format("expected {} in column '{}', found {}", expected,
                                       trim(header_.field(index)), found_text(row_.field(index))));
}

void SaleaeReader::read_header() {
  std::string_view line;
  if (!lines_.next(line)) {
    throw InputError(
        fmt::format("{}:1: expected a Saleae Logic export header ('{}' or '{}'), "
                    "found an empty file",
                    lines_.name(), kLegacyHeader, kDataTableHeader));
  }
  line = strip_bom(line);
  if (const std::size_t bad = header_.parse(line); bad != CsvRow::kOk) {
    fail(bad, "expected a CSV header with closed quotes");
  }
  layout_ = classify(header_);
  switch (layout_) {
    case SaleaeLayout::kNone:
      fail(0, fmt::format("expected a Saleae Logic export header ('{}' or '{}'), found {}",
                          kLegacyHeader, kDataTableHeader, found_text(line)));
    case SaleaeLayout::kLegacyMultiProcessor:
    case SaleaeLayout::kDataTableMultiProcessor:
      fail(0,
           "the multi-processor (MP/MDB) mode of the Async Serial analyzer is not supported; "
           "expected an export of the analyzer in its normal mode (Modbus RTU uses 8 data "
           "bits, no address bit)");
    case SaleaeLayout::kLegacy:
      time_col_ = find_column(header_, "Time [s]");
      value_col_ = find_column(header_, "Value");
      parity_col_ = find_column(header_, "Parity Error");
      framing_col_ = find_column(header_, "Framing Error");
      break;
    case SaleaeLayout::kDataTable:
      time_col_ = find_column(header_, "start_time");
      type_col_ = find_column(header_, "type");
      duration_col_ = find_column(header_, "duration");
      value_col_ = find_column(header_, "data");
      error_col_ = find_column(header_, "error");
      if (duration_col_ == kAbsent)
        fail(0, "expected a 'duration' column in the data table header");
      if (value_col_ == kAbsent) {
        fail(0,
             "expected a 'data' column in the data table header (export an Async Serial "
             "analyzer)");
      }
      break;
  }
}

Nanos SaleaeReader::parse_time(std::size_t index, bool allow_iso, int* decimals) const {
  const std::string_view text = trim(row_.field(index));
  ParsedTime t = parse_decimal_seconds(text, /*allow_exponent=*/true);
  if (!t.ok() && allow_iso && t.status == ParsedTime::Status::kSyntax) t = parse_iso8601(text);
  if (t.status == ParsedTime::Status::kOutOfRange) {
    fail_field(index, "a time within 292 years of the epoch");
  }
  if (!t.ok()) {
    fail_field(index, allow_iso ? "a time in seconds (like 0.000592672 or 8.2464e-05) or ISO 8601"
                                : "a time in seconds (like 0.042909760000000)");
  }
  if (decimals != nullptr) *decimals = t.decimals;
  return t.ns;
}

std::uint8_t SaleaeReader::parse_byte(std::size_t index) const {
  const std::string_view text = trim(row_.field(index));
  const bool hex_prefix = text.size() > 2 && text[0] == '0' && lower(text[1]) == 'x';
  bool all_hex = hex_prefix;
  for (std::size_t i = 2; all_hex && i < text.size(); ++i) all_hex = hex_digit_value(text[i]) >= 0;
  if (!all_hex) {
    fail_field(index,
               "a byte in the hex radix like 0x55 (export the analyzer with the hex "
               "display radix; decimal, ASCII and binary values are not accepted)");
  }
  const std::size_t digits = text.size() - 2;
  if (digits > 2) {
    fail_field(index, fmt::format("one byte per row like 0x55, not {} hex digits", digits));
  }
  int value = 0;
  for (std::size_t i = 2; i < text.size(); ++i) value = value * 16 + hex_digit_value(text[i]);
  return static_cast<std::uint8_t>(value);
}

std::uint8_t SaleaeReader::parse_flags() const {
  std::uint8_t flags = kLineOk;
  if (layout_ == SaleaeLayout::kLegacy) {
    for (const auto& [col, flag] :
         {std::pair{parity_col_, kParityError}, std::pair{framing_col_, kFramingError}}) {
      if (col == kAbsent) continue;
      const std::string_view cell = trim(row_.field(col));
      if (cell.empty()) continue;
      if (!iequals(cell, "Error")) fail_field(col, "'Error' or nothing");
      flags = static_cast<std::uint8_t>(flags | flag);
    }
  } else if (error_col_ != kAbsent) {
    const std::string_view cell = trim(row_.field(error_col_));
    if (iequals(cell, "parity")) {
      flags = kParityError;
    } else if (iequals(cell, "framing")) {
      flags = kFramingError;
    } else if (!cell.empty()) {
      fail_field(error_col_, "'parity', 'framing' or nothing");
    }
  }
  return flags;
}

bool SaleaeReader::next(Chunk& out) {
  std::string_view line;
  for (;;) {
    if (!lines_.next(line)) {
      clamp_.finish();
      return false;
    }
    if (!trim(line).empty()) break;
  }
  if (const std::size_t bad = row_.parse(line); bad != CsvRow::kOk) {
    fail(bad, "expected a CSV field with closed quotes followed by ',' or the end of the line");
  }
  if (type_col_ != kAbsent && !iequals(trim(row_.field(type_col_)), "data")) {
    fail_field(type_col_, "'data' (rows of an Async Serial analyzer)");
  }
  int decimals = 0;
  const Nanos start = parse_time(time_col_, layout_ == SaleaeLayout::kDataTable, &decimals);
  Nanos duration = 0;
  if (duration_col_ != kAbsent) {
    duration = parse_time(duration_col_, /*allow_iso=*/false, nullptr);
    if (duration < 0) fail_field(duration_col_, "a duration of zero or more seconds");
    if (start > 0 && duration > std::numeric_limits<Nanos>::max() - start) {
      fail_field(duration_col_, "a duration that ends within 292 years of the epoch");
    }
  }
  byte_ = parse_byte(value_col_);
  flags_ = parse_flags();
  if (decimals > max_decimals_) max_decimals_ = decimals;

  const Nanos admitted = clamp_.admit(start, trim(row_.field(time_col_)), lines_.line_number());
  out.t_first_start = admitted;
  out.time_clamped = admitted != start;
  out.t_end = admitted + duration;
  out.bytes = std::span<const std::uint8_t>(&byte_, 1);
  out.errors = std::span<const std::uint8_t>(&flags_, 1);
  out.origin = lines_.line_number();
  return true;
}

Nanos SaleaeReader::timestamp_precision() const {
  return max_decimals_ < 0 ? 0 : step_for_decimals(max_decimals_);
}

}  // namespace rtu
