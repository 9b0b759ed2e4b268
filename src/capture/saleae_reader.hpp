#pragma once
// Saleae Logic "Async Serial" exports, one byte per row, both layouts:
//
// Legacy (Logic 1.x, Logic 2 "Export to TXT/CSV", automation export_analyzer_legacy):
//   Time [s],Value,Parity Error,Framing Error
//   0.042909760000000,0x00,,Error
// Data table (Logic 2 "Export Table", automation export_data_table):
//   name,type,start_time,duration,"data"[,"error"]
//   "Async 1","data",0.000592672,8.2464e-05,0x31
//
// Columns are found by header name (any order, any case; other columns are ignored), fields
// may be quoted. Times are decimal seconds, exactly parsed, e-notation allowed; the data table
// may also carry ISO 8601 absolute times (then times are ns since 1970-01-01 UTC).
//
// Each row becomes one chunk of one byte with exact timing (TimingKind::kPerByteExact):
//   t_first_start = the start bit's time;
//   t_end = start + duration in the data table; in the legacy layout, which has no duration,
//           t_end == t_first_start, and the consumer adds the character time it knows from
//           the line settings.
// Parity and framing error columns set kParityError / kFramingError on the byte. Several
// analyzers in one data table (e.g. the two wires of a 4-wire bus) are merged in file order.
// Values must be written in the hex radix (0x55): the decimal, ASCII and binary forms are
// ambiguous or lossy, and are refused with an error that says so. The multi-processor
// (MP/MDB) mode is refused too. A start time earlier than the row before is clamped and
// reported (BackwardTimeClamp), as for text captures.
//
// Errors: InputError "FILE:LINE:COL: expected ..., found '...'" (column of the field).
// Memory stays flat; after warm-up next() allocates nothing.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "capture/capture_file.hpp"
#include "capture/capture_warnings.hpp"
#include "capture/chunk_source.hpp"
#include "capture/csv_row.hpp"
#include "capture/line_reader.hpp"

namespace rtu {

enum class SaleaeLayout : std::uint8_t {
  kNone,                    // not a Saleae export header
  kLegacy,                  // Time [s],Value,Parity Error,Framing Error
  kLegacyMultiProcessor,    // Time [s],Packet ID,Address,Data,Framing Error (refused)
  kDataTable,               // name,type,start_time,duration,"data"[,"error"]
  kDataTableMultiProcessor  // data table with an "address" column (refused)
};

// What a first line looks like (a leading UTF-8 byte-order mark is ignored).
SaleaeLayout recognise_saleae_header(std::string_view first_line);

class SaleaeReader final : public ChunkSource {
 public:
  // Reads and checks the header; throws InputError when the file cannot be opened, the header
  // is not a supported Saleae export, or a needed column is missing.
  explicit SaleaeReader(const CaptureFile& file, WarningSink warnings = print_warning_to_stderr);

  bool next(Chunk& out) override;
  [[nodiscard]] TimingKind timing_kind() const override { return TimingKind::kPerByteExact; }
  // Step of the finest start time seen so far (most decimals), as for text captures.
  [[nodiscard]] Nanos timestamp_precision() const override;
  [[nodiscard]] std::string name() const override { return lines_.name(); }
  [[nodiscard]] std::uint64_t bytes_read() const override { return lines_.bytes_read(); }
  [[nodiscard]] std::uint64_t input_size() const override { return lines_.size(); }
  [[nodiscard]] SaleaeLayout layout() const { return layout_; }

 private:
  static constexpr std::size_t kAbsent = static_cast<std::size_t>(-1);
  void read_header();
  [[noreturn]] void fail(std::size_t column0, std::string_view what) const;
  [[noreturn]] void fail_field(std::size_t index, std::string_view expected) const;
  Nanos parse_time(std::size_t index, bool allow_iso, int* decimals) const;
  std::uint8_t parse_byte(std::size_t index) const;
  std::uint8_t parse_flags() const;

  LineReader lines_;
  BackwardTimeClamp clamp_;
  CsvRow header_;
  CsvRow row_;
  SaleaeLayout layout_ = SaleaeLayout::kNone;
  std::size_t time_col_ = kAbsent;  // Time [s] or start_time
  std::size_t duration_col_ = kAbsent;
  std::size_t value_col_ = kAbsent;  // Value or data
  std::size_t type_col_ = kAbsent;
  std::size_t parity_col_ = kAbsent;
  std::size_t framing_col_ = kAbsent;
  std::size_t error_col_ = kAbsent;  // data table: "parity" / "framing"
  int max_decimals_ = -1;
  std::uint8_t byte_ = 0;
  std::uint8_t flags_ = 0;
};

}  // namespace rtu
