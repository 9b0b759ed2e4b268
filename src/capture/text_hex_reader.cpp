#include "capture/text_hex_reader.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <utility>

#include "capture/decimal_time.hpp"
#include "capture/found_text.hpp"
#include "core/hex_digits.hpp"
#include "core/input_error.hpp"

namespace rtu {
namespace {

bool is_blank(char c) {
  return c == ' ' || c == '\t';
}

std::size_t skip_blanks(std::string_view line, std::size_t pos) {
  while (pos < line.size() && is_blank(line[pos])) ++pos;
  return pos;
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c + 32) : c; };
    if (lower(a[i]) != lower(b[i])) return false;
  }
  return true;
}

std::optional<std::uint32_t> parse_baud(std::string_view text) {
  constexpr std::uint32_t kMaxBaud = 100'000'000;
  if (text.empty()) return std::nullopt;
  std::uint32_t value = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    value = value * 10U + static_cast<std::uint32_t>(c - '0');
    if (value > kMaxBaud) return std::nullopt;
  }
  if (value == 0) return std::nullopt;
  return value;
}

std::optional<Parity> parse_parity_word(std::string_view text) {
  if (auto p = parse_parity(text)) return p;
  if (iequals(text, "none")) return Parity::kNone;
  if (iequals(text, "even")) return Parity::kEven;
  if (iequals(text, "odd")) return Parity::kOdd;
  return std::nullopt;
}

}  // namespace

TextHexReader::TextHexReader(const CaptureFile& file, WarningSink warnings)
    : lines_(file), clamp_(file.name, std::move(warnings)) {
  // Room for every pair a buffer of the line reader can hold, so that reading lines in place
  // never grows it (only a longer line read line by line does, once).
  bytes_.resize(LineReader::kBufferSize / 2);
  // Read up to the first data line, so that the settings comments before it are known.
  have_pending_ = read_data_line();
}

void TextHexReader::fail(std::size_t column0, std::string_view what) const {
  throw InputError(
      fmt::format("{}:{}:{}: {}", lines_.name(), lines_.line_number(), column0 + 1, what));
}

// Returns whether the line's time went back (and was clamped to the time before).
inline bool TextHexReader::take_plain_lines(std::size_t length, std::size_t lines,
                                            std::string_view stamp, Nanos ns, int decimals) {
  lines_.take_lines(length, lines);
  if (decimals > max_decimals_) max_decimals_ = decimals;
  pending_line_ = lines_.line_number();
  pending_t_ = clamp_.admit_in_place(ns, stamp, pending_line_);
  seen_data_ = true;
  return pending_t_ != ns;
}

inline bool TextHexReader::read_plain_data_after_stamp(std::string_view text,
                                                       std::size_t stamp_length, Nanos ns,
                                                       int decimals) {
  const char* p = text.data() + stamp_length;
  const char* const end = text.data() + text.size();
  if (p == end || !is_blank(*p)) return false;
  // The constructor made room for every pair the buffer can hold, so that the loop stores
  // without a check (and nothing is allocated once reading has begun).
  if (bytes_.size() < text.size() / 2) bytes_.resize(text.size() / 2);
  std::uint8_t* const bytes = bytes_.data();
  std::size_t count = 0;
  // The shape every tool writes, " hh" after " hh" up to the '\n', without the general
  // loop's checks for other blanks and line ends; whatever else comes is left to that loop,
  // from where this one stopped (it consumes only what that loop would have).
  while (end - p >= 4 && p[0] == ' ') {
    const int value = hex_pair_value(p + 1);
    if (value < 0) break;
    bytes[count++] = static_cast<std::uint8_t>(value);
    p += 3;
  }
  // Then the line's end straight away, where it is there.
  while (p == end || p[0] != '\n') {
    while (p != end && is_blank(*p)) ++p;
    if (p == end) return false;  // the line goes on past the buffer (or the file ends)
    if (p[0] == '\n') break;
    if (end - p < 2) return false;
    if (p[0] == '\r' && p[1] == '\n') break;  // next() drops the '\r' before a '\n'
    const int value = hex_pair_value(p);
    if (value < 0) return false;
    bytes[count++] = static_cast<std::uint8_t>(value);
    p += 2;
  }
  if (count == 0) return false;
  byte_count_ = count;
  const std::size_t line_end = static_cast<std::size_t>(p - text.data()) + (p[0] == '\r' ? 2 : 1);
  pending_clamped_ = take_plain_lines(line_end, 1, text.substr(0, stamp_length), ns, decimals);
  return true;
}

bool TextHexReader::next(Chunk& out) {
  if (have_pending_) {
    have_pending_ = false;
  } else if (!read_plain_data_line() && !read_data_line()) {
    return false;
  }
  out.t_end = pending_t_;
  out.time_clamped = pending_clamped_;
  out.t_first_start = kUnknownTime;
  out.bytes = std::span<const std::uint8_t>(bytes_.data(), byte_count_);
  out.errors = {};
  out.origin = pending_line_;
  return true;
}

std::size_t TextHexReader::take_byte_lines(std::uint8_t* bytes, Nanos* t_ends, std::size_t room) {
  // What each line would update, in locals until the run ends: the stores into `bytes` may
  // alias anything (they are uint8_t), so members would be reloaded at every line.
  const std::string_view text = lines_.buffered();
  std::size_t at = 0;
  std::size_t taken = 0;
  Nanos admitted_from = clamp_.admits_from();
  int max_decimals = max_decimals_;
  std::string_view last_stamp;
  while (taken < room) {
    const std::string_view rest = text.substr(at);
    Nanos ns = 0;
    int decimals = 0;
    const std::size_t stamp_length = stamps_.scan(rest, ns, decimals);
    const char* const p = rest.data() + stamp_length;
    if (stamp_length == 0 || rest.size() - stamp_length < 4 || p[0] != ' ' || p[3] != '\n') break;
    const int value = hex_pair_value(p + 1);
    if (value < 0 || ns < admitted_from) break;  // a time going back is clamped line by line
    bytes[taken] = static_cast<std::uint8_t>(value);
    t_ends[taken] = ns;
    if (decimals > max_decimals) max_decimals = decimals;
    admitted_from = ns;
    last_stamp = rest.substr(0, stamp_length);
    at += stamp_length + 4;
    ++taken;
  }
  // In order, so admitted as it is (never clamped): the time in force is the run's last.
  if (taken > 0) (void)take_plain_lines(at, taken, last_stamp, admitted_from, max_decimals);
  return taken;
}

std::size_t TextHexReader::next_byte_reads(std::uint8_t* bytes, Nanos* t_ends, std::size_t room,
                                           std::uint64_t& first_origin) {
  if (have_pending_) return 0;
  std::size_t got = 0;
  // Plain lines follow one another with nothing between, so their origins (line numbers) do.
  while (got < room) {
    // Nearly every line of a per-byte capture is "<plain seconds> hh\n": read in runs here.
    if (const std::size_t run = take_byte_lines(bytes + got, t_ends + got, room - got); run > 0) {
      if (got == 0) first_origin = pending_line_ + 1 - run;
      got += run;
      continue;
    }
    // Any other line, and one whose time goes back, is read on its own by the general
    // plain-line reading, which leaves to next() what it cannot read.
    const std::string_view text = lines_.buffered();
    Nanos ns = 0;
    int decimals = 0;
    const std::size_t stamp_length = stamps_.scan(text, ns, decimals);
    if (stamp_length == 0 || !read_plain_data_after_stamp(text, stamp_length, ns, decimals)) {
      break;
    }
    if (byte_count_ != 1 || pending_clamped_) {
      have_pending_ = true;  // a read of several bytes, or a clamped one: next() gives it
      break;
    }
    bytes[got] = bytes_[0];
    if (got == 0) first_origin = pending_line_;
    t_ends[got] = pending_t_;
    ++got;
  }
  return got;
}

bool TextHexReader::read_data_line() {
  clamp_.keep_text();  // the line reader moves its text on
  std::string_view line;
  while (lines_.next(line)) {
    const std::size_t start = skip_blanks(line, 0);
    if (start == line.size()) continue;
    if (line[start] == '#') {
      parse_comment(line, start);
      continue;
    }
    parse_data(line, start);
    seen_data_ = true;
    return true;
  }
  clamp_.finish();
  return false;
}

bool TextHexReader::read_plain_data_line() {
  const std::string_view text = lines_.buffered();
  Nanos ns = 0;
  int decimals = 0;
  const std::size_t stamp_length = stamps_.scan(text, ns, decimals);
  return stamp_length > 0 && read_plain_data_after_stamp(text, stamp_length, ns, decimals);
}

void TextHexReader::parse_data(std::string_view line, std::size_t start) {
  // Nearly every line's stamp takes the one-pass path; the rest are cut and parsed whole.
  ParsedTime t;
  const std::string_view rest = line.substr(start);
  std::string_view stamp = rest.substr(0, parse_plain_seconds_word(rest, t));
  if (stamp.empty()) {
    stamp = word_at(line, start, '#');
    t = parse_decimal_seconds(stamp, /*allow_exponent=*/false);
  }
  if (t.status == ParsedTime::Status::kOutOfRange) {
    fail(start, fmt::format("timestamp out of range (more than 292 years from the epoch), found {}",
                            found_text(stamp)));
  }
  if (!t.ok()) {
    fail(start, fmt::format("expected a timestamp in decimal seconds (like 12.345678), found {}",
                            found_text(stamp)));
  }
  if (t.decimals > max_decimals_) max_decimals_ = t.decimals;

  if (bytes_.size() < line.size() / 2) bytes_.resize(line.size() / 2);
  byte_count_ = 0;
  std::size_t pos = start + stamp.size();
  if (pos < line.size() && !is_blank(line[pos])) {
    fail(pos, fmt::format("expected a space after the timestamp, found {}",
                          found_text(word_at(line, pos))));
  }
  for (;;) {
    pos = skip_blanks(line, pos);
    if (pos == line.size() || line[pos] == '#') break;
    const int value = pos + 1 < line.size() ? hex_pair_value(line.data() + pos) : -1;
    if (value < 0) {
      fail(pos,
           fmt::format("expected hex byte pair, found {}", found_text(word_at(line, pos, '#'))));
    }
    bytes_[byte_count_++] = static_cast<std::uint8_t>(value);
    pos += 2;
  }
  if (byte_count_ == 0) {
    fail(pos, fmt::format("expected hex bytes after the timestamp, found {}",
                          found_text(word_at(line, pos))));
  }
  pending_line_ = lines_.line_number();
  pending_t_ = clamp_.admit_in_place(t.ns, stamp, pending_line_);
  pending_clamped_ = pending_t_ != t.ns;
}

void TextHexReader::parse_comment(std::string_view line, std::size_t hash_pos) {
  std::size_t pos = hash_pos + 1;
  for (;;) {
    pos = skip_blanks(line, pos);
    if (pos >= line.size()) break;
    const std::string_view word = word_at(line, pos);
    const std::size_t eq = word.find('=');
    const std::string_view key = eq == std::string_view::npos ? word : word.substr(0, eq);
    const std::string_view value = eq == std::string_view::npos ? "" : word.substr(eq + 1);
    const std::size_t word_column = pos;
    pos += word.size();
    if (eq == std::string_view::npos) continue;  // free text
    const std::size_t value_column = word_column + eq + 1;

    PartialSettings next = settings_;
    if (iequals(key, "baud")) {
      const auto baud = parse_baud(value);
      if (!baud) {
        fail(value_column,
             fmt::format("expected a baud rate (a whole number from 1 to 100000000), found {}",
                         found_text(value)));
      }
      next.baud = baud;
    } else if (iequals(key, "parity")) {
      const auto parity = parse_parity_word(value);
      if (!parity)
        fail(value_column, fmt::format("expected parity N, E or O, found {}", found_text(value)));
      next.parity = parity;
    } else if (iequals(key, "stop")) {
      if (value != "1" && value != "2") {
        fail(value_column, fmt::format("expected stop bits 1 or 2, found {}", found_text(value)));
      }
      next.stop_bits = static_cast<std::uint8_t>(value[0] - '0');
    } else {
      continue;  // some other key=value in free text
    }
    const bool changes = next.baud != settings_.baud || next.parity != settings_.parity ||
                         next.stop_bits != settings_.stop_bits;
    if (seen_data_ && changes) {
      fail(word_column,
           fmt::format("line settings must come before the first data line; {} changes them",
                       found_text(word)));
    }
    settings_ = next;
  }
}

std::optional<LineSettings> TextHexReader::declared_settings() const {
  if (!settings_.baud && !settings_.parity && !settings_.stop_bits) return std::nullopt;
  LineSettings s;  // what the file does not say stays at the Modbus default
  if (settings_.baud) s.baud = *settings_.baud;
  if (settings_.parity) s.parity = *settings_.parity;
  if (settings_.stop_bits) s.stop_bits = *settings_.stop_bits;
  return s;
}

Nanos TextHexReader::timestamp_precision() const {
  return max_decimals_ < 0 ? 0 : step_for_decimals(max_decimals_);
}

}  // namespace rtu
