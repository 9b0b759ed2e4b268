#pragma once
// Text hex captures (.hex, .txt): one chunk per line, as a host's serial read() saw it.
//
//   # any comment; a comment may declare the line settings:
//   # baud=9600 parity=E stop=1
//   1700000000.001234 01 03 00 32 00 03 A4 04
//   1700000000.017 0103063A
//
// - The first field is the time in decimal seconds (any epoch, any number of decimals, may be
//   negative) at which the LAST byte of the line had finished arriving. It is parsed exactly
//   into nanoseconds; more than 9 decimals are rounded half away from zero.
// - Then one or more bytes as pairs of hex digits (either case), with or without spaces or
//   tabs between the pairs. A '#' after the bytes starts a trailing comment.
// - '#' as the first non-blank character makes a comment line; blank lines are ignored.
// - Settings in comments: baud=N, parity=N|E|O (or none|even|odd), stop=1|2, any subset, any
//   order, keys in any case; other words in comments are ignored. They must come before the
//   first data line; a later one that changes them is an error (it cannot be honoured: the
//   decoder has already started), a later one that repeats them is fine.
//
// Unusable input throws InputError "FILE:LINE:COL: expected ..., found '...'". A time earlier
// than the line before is clamped to it and reported through the WarningSink (see
// BackwardTimeClamp): the bytes are kept and decoded, and the user is told.
//
// Memory stays flat: one line buffer and one byte buffer, reused; after warm-up next()
// allocates nothing.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "capture/capture_file.hpp"
#include "capture/capture_warnings.hpp"
#include "capture/chunk_source.hpp"
#include "capture/line_reader.hpp"
#include "capture/stamp_shape_scanner.hpp"

namespace rtu {

class TextHexReader final : public ChunkSource {
 public:
  // Throws InputError when the file cannot be opened. Settings comments before the first data
  // line are read here already, so declared_settings() is known right after construction.
  explicit TextHexReader(const CaptureFile& file, WarningSink warnings = print_warning_to_stderr);

  bool next(Chunk& out) override;
  [[nodiscard]] std::optional<LineSettings> declared_settings() const override;
  [[nodiscard]] TimingKind timing_kind() const override { return TimingKind::kReadCompletion; }
  // The step of the FINEST timestamp seen so far (most decimals; final once the end was
  // reached). Not the coarsest: writers that drop trailing zeros ("1.5", "1.52", "1.523")
  // are common, and there fewer decimals do not mean a coarser clock. How fine the clock
  // really ticks is for the decoder to estimate from the data.
  [[nodiscard]] Nanos timestamp_precision() const override;
  [[nodiscard]] std::string name() const override { return lines_.name(); }
  [[nodiscard]] std::uint64_t bytes_read() const override { return lines_.bytes_read(); }
  [[nodiscard]] std::uint64_t input_size() const override { return lines_.size(); }

 protected:
  // Plain data lines of one byte each, parsed straight into the run (read_plain_data_line).
  std::size_t next_byte_reads(std::uint8_t* bytes, Nanos* t_ends, std::size_t room,
                              std::uint64_t& first_origin) override;

 private:
  struct PartialSettings {
    std::optional<std::uint32_t> baud;
    std::optional<Parity> parity;
    std::optional<std::uint8_t> stop_bits;
  };
  // Reads the next data line into the buffers; false at the end of the file.
  bool read_data_line();
  // The same for the shape nearly every data line has ("1700000000.123456 01 03", unsigned
  // plain decimal time, blanks, hex pairs, '\n'), parsed in place in the line reader's buffer.
  // False, with nothing consumed, for any other line (comments, errors, a line that runs past
  // the buffer): read_data_line() then reads it line by line, and gives the same chunk.
  bool read_plain_data_line();
  // The same, once the stamp at the start of `text` (the buffered text) was read. Always
  // inline, as the next one: each is the body of a line's reading, not worth a call.
  [[gnu::always_inline]] bool read_plain_data_after_stamp(std::string_view text,
                                                          std::size_t stamp_length, Nanos ns,
                                                          int decimals);
  // Reads the data lines "<plain seconds> hh\n" at the start of the buffered text, one after
  // the other and each no earlier than the one before, as next_byte_reads() would one by
  // one: up to `room` of them, and returns how many (0 where the first is not such a line).
  std::size_t take_byte_lines(std::uint8_t* bytes, Nanos* t_ends, std::size_t room);
  // Consumes the first `lines` plain data lines, `length` characters, just parsed: the last
  // one's stamp text and time, and the most decimals among them. The last is the data line
  // in force. True when its time went back and was clamped.
  [[gnu::always_inline, nodiscard]] bool take_plain_lines(std::size_t length, std::size_t lines,
                                                          std::string_view stamp, Nanos ns,
                                                          int decimals);
  void parse_comment(std::string_view line, std::size_t hash_pos);
  void parse_data(std::string_view line, std::size_t start);
  [[noreturn]] void fail(std::size_t column0, std::string_view what) const;

  LineReader lines_;
  StampShapeScanner stamps_;  // the stamps of plain data lines
  BackwardTimeClamp clamp_;
  PartialSettings settings_;
  bool seen_data_ = false;
  bool have_pending_ = false;  // a data line read ahead, for next() to give
  int max_decimals_ = -1;
  Nanos pending_t_ = 0;
  bool pending_clamped_ = false;  // pending_t_ is the time before, the line's went back
  std::uint64_t pending_line_ = 0;
  // The line's bytes are the first byte_count_ of bytes_, which is kept at least half as long
  // as any line read (a byte takes two characters), so parsing never checks for room.
  std::vector<std::uint8_t> bytes_;
  std::size_t byte_count_ = 0;
};

}  // namespace rtu
