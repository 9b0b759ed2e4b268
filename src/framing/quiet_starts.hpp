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
//
// Asking each waiting start again on every byte (a look-up, and for one that waits on its
// CRC search a step of that search) took nearly all of the framer's time where reads
// hold a byte or a few and nothing forms a frame (noise, or traffic read at the wrong baud
// rate): some 250 starts wait. So a start found still quiet is also *watched*: the framer
// steps over watched starts 64 at a time (a bit each, and a second one where the answer
// waits for bytes), and what can end a watch is checked here for all watched starts at once
// as the window grows: the window reaching `until` (the watches filed by it), and for a
// start that waits on its CRC search a zero of its CRC or a silence. The zero is not found
// by running each watched start's CRC on over each byte (that was half the framer's time
// on noise): CrcZeroIndex gives every position one value and every start a target, equal
// exactly where the CRC from the start comes out zero, so each new position compares its
// value with the watched targets, all at once. Watching only ever answers "still quiet";
// anything else ends it, and the start's own search answers again.
#include <array>
#include <cstddef>
#include <cstdint>

#include "framing/crc_zero_index.hpp"

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
  // Keeps the answer of a search that said "not yet", and returns the entry as kept. Its
  // fields are given one by one and stored one by one: a QuietStart built field by field
  // and then copied whole stalled on the copy (a wide load of the narrow stores just made,
  // which the processor cannot forward), 10% of the framer's time on per-byte reads.
  const QuietStart& remember(std::uint64_t start, std::uint64_t epoch, std::uint64_t until,
                             bool watch_crc_scan, bool pending, bool may_change) {
    unwatch(start);  // the watch was on the entry this one replaces
    QuietStart& slot = slots_[start % kSlots];
    slot.start = start;
    slot.epoch = epoch;
    slot.until = until;
    slot.watch_crc_scan = watch_crc_scan;
    slot.pending = pending;
    slot.may_change = may_change;
    return slot;
  }
  const QuietStart& remember(const QuietStart& quiet) {
    return remember(quiet.start, quiet.epoch, quiet.until, quiet.watch_crc_scan, quiet.pending,
                    quiet.may_change);
  }

  // Watches the entry find() just gave, still quiet at window end watched_through(). One
  // that waits on its CRC search is watched only where `zeros` holds the start and the
  // window end (CrcZeroIndex::compute_through() up to it): returns whether it is watched.
  // Watches of another epoch than the entry's end.
  bool watch(const QuietStart& quiet, const CrcZeroIndex& zeros);
  // The answer of a watched start: kNotWatched, or whether it waits for bytes. Valid while
  // the window end is watched_through() and the epoch the one any_watched() was asked with.
  enum Answer : std::uint8_t { kNotWatched = 0, kQuiet = 1, kQuietPending = 2 };
  [[nodiscard]] Answer watched_answer(std::uint64_t start) const {
    const std::size_t slot = start % kSlots;
    if (!test(watched_, slot)) return kNotWatched;
    return test(pending_, slot) ? kQuietPending : kQuiet;
  }
  // The first start in [from, to) that is not watched, or `to`, a word of starts at a time;
  // sets `first_pending` to the first watched start before it whose answer waits for bytes,
  // if any and if it is kNone. Starts are absolute positions, as in find(), and [from, to)
  // is at most the framer's window.
  static constexpr std::uint64_t kNone = UINT64_MAX;
  [[nodiscard]] std::uint64_t skip_watched(std::uint64_t from, std::uint64_t to,
                                           std::uint64_t& first_pending) const;
  [[nodiscard]] std::uint64_t watched_through() const { return through_; }
  [[nodiscard]] bool any_watched() const { return watchers_ > 0; }
  // Whether starts are watched in `epoch` (the answers of another one do not hold).
  [[nodiscard]] bool any_watched(std::uint64_t epoch) const {
    return watchers_ > 0 && epoch == epoch_;
  }
  // Calls settle(start) for each start whose watch the last run_on() ended at the longest frame
  // with no CRC zero, having waited on nothing else: its search would now answer a final
  // "no", as it would in any epoch. Only for watches of `epoch` (others are dropped).
  template <typename Settle>
  void take_exhausted(std::uint64_t epoch, Settle&& settle) {
    if (epoch == epoch_) {
      for (std::size_t i = 0; i < exhausted_count_; ++i) settle(exhausted_[i]);
    }
    exhausted_count_ = 0;
  }
  // Whether a watch waits on a CRC search: run_on() then needs the values up to its end.
  [[nodiscard]] bool any_crc_watched() const { return crc_watchers_ > 0; }

  // The window end moved from watched_through() to `through`, by a few bytes with no
  // silence before any of them; `zeros` holds every position up to `through` where
  // any_crc_watched(). A watch ends where the window reaches its `until`, or where the CRC
  // search it waits on comes out zero.
  void run_on(const CrcZeroIndex& zeros, std::uint64_t through);
  // The window end moved to `through` in a way watching does not follow (a silence, several
  // bytes at once): every start answers for itself again.
  void unwatch_all(std::uint64_t through) {
    through_ = through;
    if (watchers_ > 0) unwatch_every();
  }
  void unwatch(std::uint64_t start) {
    if (watchers_ > 0) unwatch_slot(start % kSlots);
  }
  // Starts [first, first + count) left the window.
  void unwatch_range(std::uint64_t first, std::size_t count) {
    if (watchers_ > 0) unwatch_slots(first, count);
  }

 private:
  static constexpr std::size_t kSlots = 2048;  // the framer's window
  static constexpr std::size_t kWords = kSlots / 64;
  void unwatch_every();
  void unwatch_slots(std::uint64_t first, std::size_t count);
  static bool test(const std::array<std::uint64_t, kWords>& bits, std::size_t slot) {
    return ((bits[slot / 64] >> (slot % 64)) & 1U) != 0;
  }
  void unwatch_slot(std::size_t slot) {  // inline: asked at every search
    if (test(watched_, slot)) unwatch_watched(slot);
  }
  void unwatch_watched(std::size_t slot);
  // Whether `slot` is in the list of CRC watches (a sparse set: index_of_ may hold anything
  // for a slot that is not).
  [[nodiscard]] bool crc_watched(std::size_t slot) const {
    const std::size_t index = index_of_[slot];
    return index < crc_watchers_ && crc_slot_[index] == slot;
  }
  void unwatch_crc_at(std::size_t index);  // the list's last watch takes its place
  void unwatch_crc_every();
  // The CRC watches' targets, to the block of watched_through(), moved on to `block`.
  void move_targets_to(const CrcZeroIndex& zeros, std::uint64_t block);
  // Whether any CRC watch's target is `value`: every one compared, branch-free, so that the
  // compiler compares several at once.
  [[nodiscard]] bool any_target_is(std::uint16_t value) const;
  void unwatch_targets(std::uint16_t value);
  // The watches whose `until` the window reached, moving from `from` to `through`, end.
  void expire(std::uint64_t from, std::uint64_t through);
  // Files a watched slot under the position where its watch ends (see due_).
  void file_due(std::size_t slot, std::uint64_t through);
  void unfile_due(std::size_t slot);

  std::array<QuietStart, kSlots> slots_{};
  // Watched starts, by slot: a bit each, set in `pending_` too where the answer waits for
  // bytes. skip_watched() reads these.
  std::array<std::uint64_t, kWords> watched_{};
  std::array<std::uint64_t, kWords> pending_{};
  std::size_t watchers_ = 0;
  // The watches that wait on a CRC search, as a list side by side: the slot and the target
  // (to block `block_` of chain `chain_` of CrcZeroIndex); and where each such slot is in
  // the list.
  std::array<std::uint16_t, kSlots> crc_slot_{};
  alignas(64) std::array<std::uint16_t, kSlots> target_{};
  std::array<std::uint16_t, kSlots> index_of_{};
  std::size_t crc_watchers_ = 0;
  std::uint64_t chain_ = 0;
  std::uint64_t block_ = 0;
  // Every watch's `until` by slot, and the watches filed by it: a ring of kDue positions
  // from the window end on, each with a doubly linked list of the slots whose watch ends
  // there. One that ends further on waits in the ring's last position and is filed again
  // from there. Watches end one or a few per byte on noise: a heap of them cost more than
  // the compares of all their targets.
  static constexpr std::size_t kDue = 512;  // more than kMaxAdu, a search's reach
  static constexpr std::uint16_t kNoSlot = UINT16_MAX;
  std::array<std::uint64_t, kSlots> until_{};
  // By slot: the watch waits on its CRC search alone, up to the longest frame. Where it
  // ends there, the start goes to exhausted_ for take_exhausted().
  std::array<bool, kSlots> exhausts_{};
  std::array<std::uint64_t, kSlots> exhausted_{};
  std::size_t exhausted_count_ = 0;
  std::array<std::uint16_t, kDue> due_first_ = [] {
    std::array<std::uint16_t, kDue> none{};
    none.fill(kNoSlot);
    return none;
  }();
  std::array<std::uint16_t, kSlots> due_next_{};
  std::array<std::uint16_t, kSlots> due_previous_{};
  std::array<std::uint16_t, kSlots> due_at_{};  // the ring position a watched slot is in
  std::uint64_t through_ = 0;
  std::uint64_t epoch_ = 0;  // of the watched entries
};

}  // namespace rtu
