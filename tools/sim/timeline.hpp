#pragma once
// The ground truth of a simulated bus: every byte that went on the wire with its exact start
// and end time, grouped into the records (frames and noise) that put it there. Records are
// kept in wire order and never overlap, so every byte belongs to exactly one record.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "adu.hpp"
#include "core/time.hpp"
#include "serial/line_settings.hpp"

namespace rtu::sim {

enum class TruthKind : std::uint8_t { kFrame, kNoise };
enum class TruthRole : std::uint8_t { kRequest, kResponse };

struct TruthRecord {
  TruthKind kind = TruthKind::kFrame;
  Nanos t_start = 0;  // start bit of the first byte
  Nanos t_end = 0;    // end of the last stop bit
  Bytes bytes;
  // Frames only.
  TruthRole role = TruthRole::kRequest;
  std::optional<std::uint64_t> txn;      // shared by a request and its response
  std::vector<std::string_view> faults;  // injected faults, as issue-catalogue keys
  std::string_view device;               // profile that sent or was asked
  // Heavy profile only (classic truth files keep their format): the indices of the bytes a
  // bit flip changed, and the size a truncated frame was meant to have.
  std::vector<std::size_t> flipped;
  std::size_t intended_size = 0;
  // Noise only: "burst" (interference), "turnaround" (driver switching, 0x00/0xFF bytes)
  // or "glitch" (one byte right after a frame, heavy profile).
  std::string_view cause;
};

TruthRecord frame_record(Bytes bytes, TruthRole role, std::uint64_t txn, std::string_view device);
TruthRecord noise_record(Bytes bytes, std::string_view cause);

struct WireByte {
  std::uint8_t value = 0;
  Nanos start = 0;
  Nanos end = 0;
};

class Timeline {
 public:
  explicit Timeline(const LineSettings& line) : line_(line) {}

  // Puts the record's bytes on the wire from `start`, one character time each, with
  // `gap_after(k)` extra silence after byte k (only between bytes of the record). `start`
  // must not precede the end of the previous record. Fills t_start/t_end; returns t_end.
  // Whatever caused them, a frame that starts less than t3.5 after the previous record gets
  // the fault "t3.5" and one with a silence over t1.5 inside gets "t1.5", so the truth
  // names every timing violation a decoder can observe.
  template <typename GapFn>
  Nanos emit(TruthRecord record, Nanos start, GapFn gap_after) {
    check_start(start);
    const bool frame = record.kind == TruthKind::kFrame;
    if (frame && !bytes_.empty() && start - wire_end() < line_.t3_5()) add_fault(record, "t3.5");
    Nanos t = start;
    record.t_start = start;
    for (std::size_t k = 0; k < record.bytes.size(); ++k) {
      if (k > 0) {
        const Nanos gap = gap_after(k - 1);
        if (frame && gap > line_.t1_5()) add_fault(record, "t1.5");
        t += gap;
      }
      const Nanos end = t + char_time_;
      bytes_.push_back({record.bytes[k], t, end});
      t = end;
    }
    record.t_end = t;
    records_.push_back(std::move(record));
    return t;
  }
  Nanos emit(TruthRecord record, Nanos start) {
    return emit(std::move(record), start, [](std::size_t) { return Nanos{0}; });
  }

  // End of the last byte on the wire (or 0 before the first).
  [[nodiscard]] Nanos wire_end() const { return bytes_.empty() ? 0 : bytes_.back().end; }
  [[nodiscard]] const LineSettings& line() const { return line_; }
  [[nodiscard]] Nanos char_time() const { return char_time_; }
  [[nodiscard]] const std::vector<TruthRecord>& records() const { return records_; }
  [[nodiscard]] const std::vector<WireByte>& bytes() const { return bytes_; }

 private:
  void check_start(Nanos start) const;
  static void add_fault(TruthRecord& record, std::string_view fault);

  LineSettings line_;
  // Exact to the nanosecond: bits per character (start + 8 + parity + stop) / baud.
  Nanos char_time_ = line_.char_time();
  std::vector<TruthRecord> records_;
  std::vector<WireByte> bytes_;
};

}  // namespace rtu::sim
