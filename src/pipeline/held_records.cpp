#include "pipeline/held_records.hpp"

#include <bit>
#include <cstring>
#include <type_traits>

namespace rtu {
namespace {

// An entry starts with one byte: bit 0 tells a decided time from a record; a record's other
// bits tell its kind and which of its rarer fields follow.
constexpr std::uint8_t kAdvance = 1U << 0U;
constexpr std::uint8_t kNoise = 1U << 1U;
constexpr std::uint8_t kCrcOk = 1U << 2U;
constexpr std::uint8_t kHasIssues = 1U << 3U;
constexpr std::uint8_t kHasLineErrors = 1U << 4U;
constexpr std::uint8_t kHasShapeFit = 1U << 5U;
constexpr std::uint8_t kHasGap = 1U << 6U;
// An entry of its own: the capture broke (no record entry sets kAdvance).
constexpr std::uint8_t kBreak = kAdvance | (1U << 7U);

// Numbers as 7 bits a byte, least significant first, the top bit saying more follow: ten
// bytes at most for 64 bits.
constexpr std::size_t kMaxVarint = 10;

std::uint8_t* put_varint(std::uint8_t* at, std::uint64_t v) {
  while (v >= 0x80U) {
    *at++ = static_cast<std::uint8_t>(v | 0x80U);
    v >>= 7U;
  }
  *at++ = static_cast<std::uint8_t>(v);
  return at;
}

std::uint64_t get_varint(const std::uint8_t*& at) {
  std::uint64_t v = 0;
  for (unsigned shift = 0;; shift += 7) {
    const std::uint8_t b = *at++;
    v |= std::uint64_t{b & 0x7FU} << shift;
    if ((b & 0x80U) == 0) return v;
  }
}

// A difference of two 64-bit values, wrapping (kUnknownTime and times that go backwards
// included), mapped so that small differences of either sign are small numbers.
std::uint64_t zigzag(std::uint64_t value, std::uint64_t base) {
  const std::uint64_t d = value - base;
  return (d << 1U) ^ (0 - (d >> 63U));
}

std::uint64_t unzigzag(std::uint64_t z, std::uint64_t base) {
  const std::uint64_t d = (z >> 1U) ^ (0 - (z & 1U));
  return base + d;
}

std::uint64_t bits_of(Nanos t) {
  return std::bit_cast<std::uint64_t>(t);
}
Nanos time_of(std::uint64_t bits) {
  return std::bit_cast<Nanos>(bits);
}

// The most a record's entry takes besides its bytes: flags, six numbers, shape fit, line
// errors and issues.
constexpr std::size_t kMaxRecordEntry = 1 + 6 * kMaxVarint + 1 + 1 + sizeof(IssueSet);

}  // namespace

std::uint8_t* HeldRecords::room_for(std::size_t size) {
  if (blocks_.empty() || used_.back() + size > kBlockBytes) {
    // Not make_unique: the block need not be zeroed, every byte read back is written first.
    blocks_.emplace_back(new std::uint8_t[kBlockBytes]);
    used_.push_back(0);
  }
  return block() + used_.back();
}

void HeldRecords::flush_advance() {
  if (!advance_pending_) return;
  std::uint8_t* at = room_for(1 + kMaxVarint);
  *at++ = kAdvance;
  at = put_varint(at, zigzag(bits_of(pending_advance_), bits_of(last_held_.t_end)));
  commit(at);
  advance_pending_ = false;
}

void HeldRecords::hold_advance(Nanos now) {
  pending_advance_ = now;
  advance_pending_ = true;
}

void HeldRecords::hold_break() {
  flush_advance();
  std::uint8_t* at = room_for(1);
  *at++ = kBreak;
  commit(at);
}

void HeldRecords::hold(const Record& record) {
  static_assert(std::is_trivially_copyable_v<IssueSet>, "held as bytes");
  flush_advance();
  std::uint8_t flags = 0;
  if (record.kind == RecordKind::kNoise) flags |= kNoise;
  if (record.crc_ok) flags |= kCrcOk;
  if (!record.issues.empty()) flags |= kHasIssues;
  if (record.line_errors != 0) flags |= kHasLineErrors;
  if (record.shape_fit != kFitsNone) flags |= kHasShapeFit;
  if (record.gap_before != kUnknownTime) flags |= kHasGap;
  std::uint8_t* at = room_for(kMaxRecordEntry + record.size);
  *at++ = flags;
  at = put_varint(at, zigzag(record.seq, last_held_.seq));
  at = put_varint(at, zigzag(record.origin, last_held_.origin));
  at = put_varint(at, zigzag(bits_of(record.t_start), bits_of(last_held_.t_end)));
  at = put_varint(at, zigzag(bits_of(record.t_end), bits_of(record.t_start)));
  if ((flags & kHasGap) != 0) at = put_varint(at, zigzag(bits_of(record.gap_before), 0));
  at = put_varint(at, record.size);
  if ((flags & kHasShapeFit) != 0) *at++ = record.shape_fit;
  if ((flags & kHasLineErrors) != 0) *at++ = record.line_errors;
  if ((flags & kHasIssues) != 0) {
    std::memcpy(at, &record.issues, sizeof(IssueSet));
    at += sizeof(IssueSet);
  }
  std::memcpy(at, record.storage.data(), record.size);
  commit(at + record.size);
  last_held_ = Previous{record.seq, record.origin, record.t_end};
}

void HeldRecords::tell(PairingInput& pairing) {
  flush_advance();
  Record record;
  Previous last;
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    const std::uint8_t* at = blocks_[b].get();
    const std::uint8_t* const end = at + used_[b];
    while (at < end) {
      const std::uint8_t flags = *at++;
      if (flags == kBreak) {
        pairing.on_break();
        continue;
      }
      if ((flags & kAdvance) != 0) {
        pairing.advance(time_of(unzigzag(get_varint(at), bits_of(last.t_end))));
        continue;
      }
      record.reset_keeping_storage();
      record.kind = (flags & kNoise) != 0 ? RecordKind::kNoise : RecordKind::kFrame;
      record.crc_ok = (flags & kCrcOk) != 0;
      record.seq = unzigzag(get_varint(at), last.seq);
      record.origin = unzigzag(get_varint(at), last.origin);
      record.t_start = time_of(unzigzag(get_varint(at), bits_of(last.t_end)));
      record.t_end = time_of(unzigzag(get_varint(at), bits_of(record.t_start)));
      if ((flags & kHasGap) != 0) record.gap_before = time_of(unzigzag(get_varint(at), 0));
      record.size = static_cast<std::uint16_t>(get_varint(at));
      if ((flags & kHasShapeFit) != 0) record.shape_fit = *at++;
      if ((flags & kHasLineErrors) != 0) record.line_errors = *at++;
      if ((flags & kHasIssues) != 0) {
        std::memcpy(&record.issues, at, sizeof(IssueSet));
        at += sizeof(IssueSet);
      }
      std::memcpy(record.storage.data(), at, record.size);
      at += record.size;
      last = Previous{record.seq, record.origin, record.t_end};
      pairing.on_record(record);
    }
    blocks_[b].reset();  // told: its memory goes back at once
  }
  blocks_.clear();
  used_.clear();
  last_held_ = Previous{};
}

}  // namespace rtu
