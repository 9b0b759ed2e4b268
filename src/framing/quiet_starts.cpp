#include "framing/quiet_starts.hpp"

#include <algorithm>
#include <bit>

namespace rtu {

bool QuietStarts::watch(const QuietStart& quiet, const CrcZeroIndex& zeros) {
  if (quiet.epoch != epoch_) {
    unwatch_every();
    epoch_ = quiet.epoch;
  }
  const std::size_t slot = quiet.start % kSlots;
  unwatch_slot(slot);  // a watch made again starts afresh
  if (quiet.watch_crc_scan) {
    if (!zeros.holds(quiet.start) || !zeros.holds(through_)) return false;
    if (crc_watchers_ > 0 && zeros.chain() != chain_) unwatch_crc_every();
    if (crc_watchers_ == 0) {
      chain_ = zeros.chain();
      block_ = zeros.block_of(through_);
    }
    // The target to the block of the window end: the start's own, or the one after it
    // (a search reaches no further, see CrcZeroIndex).
    std::uint16_t target = zeros.target_of(quiet.start);
    const std::uint64_t start_block = zeros.block_of(quiet.start);
    if (start_block + 1 == block_) {
      target = zeros.moved_on(target, start_block);
    } else if (start_block != block_) {
      return false;
    }
    const std::size_t index = crc_watchers_++;
    crc_slot_[index] = static_cast<std::uint16_t>(slot);
    target_[index] = target;
    index_of_[slot] = static_cast<std::uint16_t>(index);
  }
  const std::uint64_t bit = std::uint64_t{1} << (slot % 64);
  watched_[slot / 64] |= bit;
  if (quiet.pending) pending_[slot / 64] |= bit;
  ++watchers_;
  until_[slot] = quiet.until;
  exhausts_[slot] = quiet.watch_crc_scan && !quiet.pending && quiet.until == quiet.start + kMaxAdu;
  file_due(slot, through_);
  return true;
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

void QuietStarts::run_on(const CrcZeroIndex& zeros, std::uint64_t through) {
  const std::uint64_t from = through_;
  through_ = through;
  exhausted_count_ = 0;  // what the last run_on() found is taken or dropped
  if (crc_watchers_ > 0) {
    if (zeros.chain() != chain_ || !zeros.holds(through)) {
      unwatch_crc_every();  // the values the targets were made for are gone
    } else {
      for (std::uint64_t position = from + 1; position <= through && crc_watchers_ > 0;
           ++position) {
        const std::uint64_t block = zeros.block_of(position);
        if (block != block_) move_targets_to(zeros, block);
        const std::uint16_t value = zeros.value_at(position);
        if (any_target_is(value)) unwatch_targets(value);
      }
    }
  }
  expire(from, through);
}

void QuietStarts::move_targets_to(const CrcZeroIndex& zeros, std::uint64_t block) {
  if (block != block_ + 1) {
    unwatch_crc_every();
    return;
  }
  for (std::size_t i = 0; i < crc_watchers_;) {
    // A target moves on once: a start in an earlier block would have reached its until.
    if (zeros.block_of(slots_[crc_slot_[i]].start) != block_) {
      unwatch_slot(crc_slot_[i]);  // the last watch moves to i: it is looked at next
    } else {
      target_[i] = zeros.moved_on(target_[i], block_);
      ++i;
    }
  }
  block_ = block;
}

bool QuietStarts::any_target_is(std::uint16_t value) const {
  std::uint16_t hits = 0;
  for (std::size_t i = 0; i < crc_watchers_; ++i) {
    hits |= static_cast<std::uint16_t>(target_[i] == value);
  }
  return hits != 0;
}

void QuietStarts::unwatch_targets(std::uint16_t value) {
  for (std::size_t i = 0; i < crc_watchers_;) {
    if (target_[i] == value) {
      unwatch_slot(crc_slot_[i]);  // the last watch moves to i: it is looked at next
    } else {
      ++i;
    }
  }
}

void QuietStarts::file_due(std::size_t slot, std::uint64_t through) {
  const std::uint64_t due = std::min<std::uint64_t>(until_[slot], through + kDue - 1);
  const auto at = static_cast<std::uint16_t>(due % kDue);
  const std::uint16_t first = due_first_[at];
  due_next_[slot] = first;
  due_previous_[slot] = kNoSlot;
  if (first != kNoSlot) due_previous_[first] = static_cast<std::uint16_t>(slot);
  due_first_[at] = static_cast<std::uint16_t>(slot);
  due_at_[slot] = at;
}

void QuietStarts::unfile_due(std::size_t slot) {
  const std::uint16_t next = due_next_[slot];
  const std::uint16_t previous = due_previous_[slot];
  if (previous == kNoSlot) {
    due_first_[due_at_[slot]] = next;
  } else {
    due_next_[previous] = next;
  }
  if (next != kNoSlot) due_previous_[next] = previous;
}

void QuietStarts::expire(std::uint64_t from, std::uint64_t through) {
  const std::uint64_t last = std::min(through, from + kDue);  // the ring once round at most
  for (std::uint64_t position = from + 1; position <= last && watchers_ > 0; ++position) {
    std::uint16_t slot = due_first_[position % kDue];
    while (slot != kNoSlot) {
      const std::uint16_t next = due_next_[slot];
      if (until_[slot] <= through) {
        // A zero up to there would have ended the watch first (run_on()).
        if (exhausts_[slot]) exhausted_[exhausted_count_++] = slots_[slot].start;
        unwatch_slot(slot);
      } else {
        unfile_due(slot);  // it waited at the ring's end: further on now
        file_due(slot, through);
      }
      slot = next;
    }
  }
}

void QuietStarts::unwatch_watched(std::size_t slot) {
  const std::uint64_t clear = ~(std::uint64_t{1} << (slot % 64));
  watched_[slot / 64] &= clear;
  pending_[slot / 64] &= clear;
  --watchers_;
  unfile_due(slot);
  if (crc_watched(slot)) unwatch_crc_at(index_of_[slot]);
}

void QuietStarts::unwatch_crc_at(std::size_t index) {
  const std::size_t last = --crc_watchers_;
  if (index != last) {
    crc_slot_[index] = crc_slot_[last];
    target_[index] = target_[last];
    index_of_[crc_slot_[index]] = static_cast<std::uint16_t>(index);
  }
}

void QuietStarts::unwatch_crc_every() {
  while (crc_watchers_ > 0) unwatch_slot(crc_slot_[crc_watchers_ - 1]);
}

void QuietStarts::unwatch_slots(std::uint64_t first, std::size_t count) {
  for (std::size_t i = 0; i < count && watchers_ > 0; ++i) unwatch_slot((first + i) % kSlots);
}

void QuietStarts::unwatch_every() {
  // The ring's lists hold watched slots only: emptied where those are.
  for (std::size_t word = 0; word < kWords && watchers_ > 0; ++word) {
    for (std::uint64_t bits = watched_[word]; bits != 0; bits &= bits - 1) {
      due_first_[due_at_[word * 64 + static_cast<std::size_t>(std::countr_zero(bits))]] = kNoSlot;
      --watchers_;
    }
  }
  watched_.fill(0);
  pending_.fill(0);
  watchers_ = 0;
  crc_watchers_ = 0;
}

}  // namespace rtu
