#pragma once
// Start positions whose last search for a frame said "not yet", kept with what alone can
// change that answer, so that the framer does not search them again on every byte.
//
// On traffic of unknown function codes every buffered byte may start a frame of no known
// length, and each stays undecided until its CRC search meets a zero or a silence. Without
// this, every position of an undecided stretch is searched again whenever a byte comes:
// quadratic in the stretch, six times the cost of ordinary polling on random frames with
// per-byte reads. The answer for a start depends only on its bytes, the silences before
// them, the timing resolution and what the bus awaits next (the role tried first); the last
// two mark an epoch, and a change of either starts a new one. Within an epoch, a search
// that waited only for
//   - a predicted length to arrive (a response's byte count, a fixed size), or
//   - its CRC search to come upon a zero or a silence
// repeats its answer until the window reaches `until` or the CRC search finds either.
#include <array>
#include <cstddef>
#include <cstdint>

namespace rtu {

struct QuietStart {
  static constexpr std::uint64_t kNever = UINT64_MAX;

  std::uint64_t start = kNever;  // absolute position of the first byte
  std::uint64_t epoch = 0;       // the framer's epoch when it was searched
  // The absolute window end at which a predicted length is complete, or the CRC search
  // reaches the longest frame: the answer may change from there on.
  std::uint64_t until = kNever;
  bool watch_crc_scan = false;  // a zero or a silence in the CRC search changes it too
  // The answer to repeat: the search waits for bytes (`pending`), or it found nothing yet
  // and more bytes may still confirm something (`may_change`).
  bool pending = false;
  bool may_change = false;
};

// What a search at full depth notes for QuietStart (see Framer::confirmed_length).
struct SearchNotes {
  std::uint64_t until = QuietStart::kNever;
  bool watch_crc_scan = false;
  bool next_byte_matters = false;  // e.g. a shape that needs one more byte: not quiet
};

// Direct-mapped on the start position, like CrcScanCache; a collision only costs a search.
class QuietStarts {
 public:
  // The entry for `start` made in `epoch` that still holds at window end `window_end`.
  [[nodiscard]] const QuietStart* find(std::uint64_t start, std::uint64_t epoch,
                                       std::uint64_t window_end) const {
    const QuietStart& q = slots_[start % kSlots];
    if (q.start != start || q.epoch != epoch || window_end >= q.until) return nullptr;
    return &q;
  }
  void remember(const QuietStart& quiet) { slots_[quiet.start % kSlots] = quiet; }

 private:
  static constexpr std::size_t kSlots = 2048;  // the framer's window
  std::array<QuietStart, kSlots> slots_{};
};

}  // namespace rtu
