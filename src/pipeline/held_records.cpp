#include "pipeline/held_records.hpp"

#include <cstring>
#include <type_traits>

namespace rtu {

struct HeldRecords::Header {
  Nanos t_start;
  Nanos t_end;
  Nanos gap_before;
  std::uint64_t seq;
  std::uint64_t origin;
  IssueSet issues;
  std::uint16_t size;
  RecordKind kind;
  std::uint8_t line_errors;
  std::uint8_t shape_fit;
  bool crc_ok;
};
std::uint8_t* HeldRecords::room_for(std::size_t size) {
  if (blocks_.empty() || used_.back() + size > kBlockBytes) {
    // Not make_unique: the block need not be zeroed, every byte read back is written first.
    blocks_.emplace_back(new std::uint8_t[kBlockBytes]);
    used_.push_back(0);
  }
  std::uint8_t* at = blocks_.back().get() + used_.back();
  used_.back() += size;
  return at;
}

void HeldRecords::flush_advance() {
  if (!advance_pending_) return;
  std::uint8_t* at = room_for(1 + sizeof(Nanos));
  at[0] = static_cast<std::uint8_t>(Tag::kAdvance);
  std::memcpy(at + 1, &pending_advance_, sizeof(Nanos));
  advance_pending_ = false;
}

void HeldRecords::hold_advance(Nanos now) {
  pending_advance_ = now;
  advance_pending_ = true;
}

void HeldRecords::hold(const Record& record) {
  static_assert(std::is_trivially_copyable_v<Header>, "held as bytes");
  flush_advance();
  const Header header{record.t_start,     record.t_end,     record.gap_before, record.seq,
                      record.origin,      record.issues,    record.size,       record.kind,
                      record.line_errors, record.shape_fit, record.crc_ok};
  std::uint8_t* at = room_for(1 + sizeof(Header) + record.size);
  at[0] = static_cast<std::uint8_t>(Tag::kRecord);
  std::memcpy(at + 1, &header, sizeof(Header));
  std::memcpy(at + 1 + sizeof(Header), record.storage.data(), record.size);
}

void HeldRecords::tell(PairingInput& pairing) {
  flush_advance();
  Record record;
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    const std::uint8_t* at = blocks_[b].get();
    const std::uint8_t* const end = at + used_[b];
    while (at < end) {
      if (static_cast<Tag>(*at++) == Tag::kAdvance) {
        Nanos now = 0;
        std::memcpy(&now, at, sizeof(Nanos));
        at += sizeof(Nanos);
        pairing.advance(now);
        continue;
      }
      Header header{};
      std::memcpy(&header, at, sizeof(Header));
      at += sizeof(Header);
      record.reset_keeping_storage();
      record.kind = header.kind;
      record.seq = header.seq;
      record.t_start = header.t_start;
      record.t_end = header.t_end;
      record.gap_before = header.gap_before;
      record.origin = header.origin;
      record.size = header.size;
      record.line_errors = header.line_errors;
      record.shape_fit = header.shape_fit;
      record.crc_ok = header.crc_ok;
      record.issues = header.issues;
      std::memcpy(record.storage.data(), at, header.size);
      at += header.size;
      pairing.on_record(record);
    }
    blocks_[b].reset();  // told: its memory goes back at once
  }
  blocks_.clear();
  used_.clear();
}

}  // namespace rtu
