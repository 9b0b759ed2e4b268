#pragma once
// What the framing tells the pairing (records and decided times), held compactly in memory
// to be told later, exactly as it came: a sample's records wait here while the sample is
// looked at first (pipeline/first_look_gate.hpp). A record keeps the fields the framing sets
// and only the bytes in use, not a whole Record's 368 bytes. Its times, sequence number and
// origin are held as differences from the record before it, a few bytes each on a bus's
// regular traffic: a polling frame and the decided time after it take about 28 bytes besides
// the frame's own, where a fixed header took 66 (peak memory of a per-byte report of 5 M
// frames: 33 -> 26 MB).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/time.hpp"
#include "framing/record.hpp"
#include "pairing/pairing_input.hpp"

namespace rtu {

class HeldRecords {
 public:
  // The record as the framing made it; the pairing's fields (role, txn...) are not kept.
  void hold(const Record& record);
  // No record can start before `now`. Consecutive decided times keep only the last: the
  // pairing's verdicts never depend on when it was told a time (TransactionTracker::advance).
  void hold_advance(Nanos now);
  // The capture broke here (PairingInput::on_break).
  void hold_break();
  // Tells `pairing` everything held, in order, and forgets it (its memory is given back).
  void tell(PairingInput& pairing);

  // Bytes of memory taken now.
  [[nodiscard]] std::size_t bytes_held() const { return blocks_.size() * kBlockBytes; }

 private:
  static constexpr std::size_t kBlockBytes = 256 * 1024;

  // Writes a decided time still pending (one comes before the next record, as it came).
  void flush_advance();
  // Where at most `size` bytes go next: the current block, or a new one when it cannot take
  // them whole (an entry never spans two blocks). commit() says how many were written.
  std::uint8_t* room_for(std::size_t size);
  void commit(const std::uint8_t* end) { used_.back() = static_cast<std::size_t>(end - block()); }
  [[nodiscard]] std::uint8_t* block() const { return blocks_.back().get(); }

  std::vector<std::unique_ptr<std::uint8_t[]>> blocks_;
  std::vector<std::size_t> used_;  // bytes written in each block
  Nanos pending_advance_ = kUnknownTime;
  bool advance_pending_ = false;
  // What the next entry is held as a difference from: the last record's.
  struct Previous {
    std::uint64_t seq = 0;
    std::uint64_t origin = 0;
    Nanos t_end = 0;
  };
  Previous last_held_;
};

}  // namespace rtu
