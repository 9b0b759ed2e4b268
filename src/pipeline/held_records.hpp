#pragma once
// What the framing tells the pairing (records and decided times), held compactly in memory
// to be told later, exactly as it came: a sample's records wait here while the sample is
// looked at first (pipeline/first_look_gate.hpp). A record keeps the fields the framing sets
// and only the bytes in use, so a short frame costs about 90 bytes, not a whole Record's 368.
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
  // Tells `pairing` everything held, in order, and forgets it (its memory is given back).
  void tell(PairingInput& pairing);

  // Bytes of memory taken now.
  [[nodiscard]] std::size_t bytes_held() const { return blocks_.size() * kBlockBytes; }

 private:
  static constexpr std::size_t kBlockBytes = 256 * 1024;
  struct Header;  // a record's fields, as held
  enum class Tag : std::uint8_t { kRecord, kAdvance };

  // Writes a decided time still pending (one comes before the next record, as it came).
  void flush_advance();
  // Where `size` bytes go next: the current block, or a new one when it cannot take them
  // whole (an entry never spans two blocks).
  std::uint8_t* room_for(std::size_t size);

  std::vector<std::unique_ptr<std::uint8_t[]>> blocks_;
  std::vector<std::size_t> used_;  // bytes written in each block
  Nanos pending_advance_ = kUnknownTime;
  bool advance_pending_ = false;
};

}  // namespace rtu
