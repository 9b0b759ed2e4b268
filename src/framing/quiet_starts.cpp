#include "framing/quiet_starts.hpp"

#include "core/crc16.hpp"

namespace rtu {

void QuietStarts::watch(const QuietStart& quiet, std::uint16_t crc) {
  if (quiet.epoch != epoch_) {
    unwatch_every();
    epoch_ = quiet.epoch;
  }
  const std::size_t slot = quiet.start % kSlots;
  until_[slot] = quiet.until;
  crc_[slot] = crc;
  crc_ends_[slot] = quiet.watch_crc_scan;
  if (answer_[slot] == kNotWatched) {
    watched_[slot / 64] |= std::uint64_t{1} << (slot % 64);
    ++watchers_;
  }
  answer_[slot] = quiet.pending ? kQuietPending : kQuiet;
}

void QuietStarts::run_on(std::span<const std::uint8_t> bytes, std::uint64_t through) {
  through_ = through;
  if (bytes.size() == 1) {
    run_on_one(bytes[0], through);
    return;
  }
  for_each_watched([&](std::size_t slot) {
    std::uint16_t crc = crc_[slot];
    bool zero = false;
    for (const std::uint8_t b : bytes) {
      crc = crc16_update(crc, b);
      zero = zero || crc == 0;
    }
    crc_[slot] = crc;
    return through >= until_[slot] || (zero && crc_ends_[slot]);
  });
}

// run_on() over one byte, what per-byte reads bring: kept apart, it is the framer's
// hottest loop on a stretch that forms nothing.
void QuietStarts::run_on_one(std::uint8_t byte, std::uint64_t through) {
  for_each_watched([&](std::size_t slot) {
    // Every register runs on, watched search or not: a branch per start cost more.
    const std::uint16_t crc = crc16_update(crc_[slot], byte);
    crc_[slot] = crc;
    return (through >= until_[slot]) | ((crc == 0) & crc_ends_[slot]);
  });
}

void QuietStarts::unwatch_slots(std::uint64_t first, std::size_t count) {
  for (std::size_t i = 0; i < count && watchers_ > 0; ++i) unwatch_slot((first + i) % kSlots);
}

void QuietStarts::unwatch_every() {
  for_each_watched([](std::size_t /*slot*/) { return true; });
}

}  // namespace rtu
