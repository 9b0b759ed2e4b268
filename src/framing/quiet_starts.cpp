#include "framing/quiet_starts.hpp"

#include <algorithm>
#include <bit>

#include "core/crc16.hpp"

namespace rtu {

void QuietStarts::watch(const QuietStart& quiet, std::uint16_t crc) {
  if (quiet.epoch != epoch_) {
    unwatch_every();
    epoch_ = quiet.epoch;
  }
  const std::size_t slot = quiet.start % kSlots;
  const std::uint64_t bit = std::uint64_t{1} << (slot % 64);
  std::size_t index = index_of_[slot];
  if (!test(watched_, slot)) {
    watched_[slot / 64] |= bit;
    index = watchers_++;
    watch_slot_[index] = static_cast<std::uint16_t>(slot);
    index_of_[slot] = static_cast<std::uint16_t>(index);
  }
  until_[index] = quiet.until;
  crc_[index] = crc;
  crc_ends_[index] = quiet.watch_crc_scan;
  if (quiet.pending) {
    pending_[slot / 64] |= bit;
  } else {
    pending_[slot / 64] &= ~bit;
  }
}

std::uint64_t QuietStarts::skip_watched(std::uint64_t from, std::uint64_t to,
                                        std::uint64_t& first_pending) const {
  for (std::uint64_t start = from; start < to;) {
    const std::size_t slot = start % kSlots;
    const std::size_t shift = slot % 64;
    const std::uint64_t count = std::min<std::uint64_t>(64 - shift, to - start);
    // The word's bits for [start, start + count), from bit 0 on.
    const std::uint64_t in_range =
        count == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << count) - 1;
    const std::uint64_t unwatched = ~(watched_[slot / 64] >> shift) & in_range;
    if (first_pending == kNone) {
      const std::uint64_t before = unwatched == 0 ? in_range : (unwatched & -unwatched) - 1;
      const std::uint64_t pending = (pending_[slot / 64] >> shift) & before;
      if (pending != 0) {
        first_pending = start + static_cast<std::uint64_t>(std::countr_zero(pending));
      }
    }
    if (unwatched != 0) return start + static_cast<std::uint64_t>(std::countr_zero(unwatched));
    start += count;
  }
  return to;
}

void QuietStarts::run_on(std::span<const std::uint8_t> bytes, std::uint64_t through) {
  through_ = through;
  if (bytes.size() == 1) {
    run_on_one(bytes[0], through);
    return;
  }
  for (std::size_t i = 0; i < watchers_;) {
    std::uint16_t crc = crc_[i];
    bool zero = false;
    for (const std::uint8_t b : bytes) {
      crc = crc16_update(crc, b);
      zero = zero || crc == 0;
    }
    crc_[i] = crc;
    if (through >= until_[i] || (zero && crc_ends_[i])) {
      unwatch_at(i);  // the last watch moves to i: it is looked at next
    } else {
      ++i;
    }
  }
}

// run_on() over one byte, what per-byte reads bring: kept apart, it is the framer's
// hottest loop on a stretch that forms nothing.
void QuietStarts::run_on_one(std::uint8_t byte, std::uint64_t through) {
  for (std::size_t i = 0; i < watchers_;) {
    // Every register runs on, watched search or not: a branch per start cost more.
    const std::uint16_t crc = crc16_update(crc_[i], byte);
    crc_[i] = crc;
    if ((through >= until_[i]) | ((crc == 0) & crc_ends_[i])) {
      unwatch_at(i);  // the last watch moves to i: it is looked at next
    } else {
      ++i;
    }
  }
}

void QuietStarts::unwatch_at(std::size_t index) {
  const std::size_t slot = watch_slot_[index];
  const std::uint64_t clear = ~(std::uint64_t{1} << (slot % 64));
  watched_[slot / 64] &= clear;
  pending_[slot / 64] &= clear;
  const std::size_t last = --watchers_;
  if (index != last) {
    watch_slot_[index] = watch_slot_[last];
    until_[index] = until_[last];
    crc_[index] = crc_[last];
    crc_ends_[index] = crc_ends_[last];
    index_of_[watch_slot_[index]] = static_cast<std::uint16_t>(index);
  }
}

void QuietStarts::unwatch_slots(std::uint64_t first, std::size_t count) {
  for (std::size_t i = 0; i < count && watchers_ > 0; ++i) unwatch_slot((first + i) % kSlots);
}

void QuietStarts::unwatch_every() {
  watched_.fill(0);
  pending_.fill(0);
  watchers_ = 0;
}

}  // namespace rtu
