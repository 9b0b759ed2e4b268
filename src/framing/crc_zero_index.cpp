#include "framing/crc_zero_index.hpp"

#include <algorithm>
#include <stdexcept>

#include "core/crc16.hpp"

namespace rtu {
namespace {

constexpr std::size_t kBlock = CrcZeroIndex::kBlock;
// Searches extended by fewer positions than this compare each one.
constexpr std::uint64_t kCompareUpTo = 4;

struct Tables {
  // step[j][b] = A^-j T[b]: byte b's term in the value of the position j after the base.
  std::array<std::array<std::uint16_t, 256>, kBlock + 1> step{};
  // A^-o I: the initial register's term in the target of a start o after the base.
  std::array<std::uint16_t, kBlock> initial{};
  // A^kBlock, by the low and the high byte: moves a value to the next block's base.
  std::array<std::uint16_t, 256> to_next_low{};
  std::array<std::uint16_t, 256> to_next_high{};

  Tables() {
    // A's inverse: the high byte of A(c) is the high byte of T[c & 0xFF], and those 256 high
    // bytes differ (the CRC polynomial's top term makes them so), so c's low byte is read
    // back from it, and then c's high byte from A(c)'s low byte.
    std::array<int, 256> low_of_high{};
    low_of_high.fill(-1);
    for (unsigned i = 0; i < 256; ++i) {
      const unsigned high = crc_detail::kTable[i] >> 8U;
      if (low_of_high[high] >= 0) throw std::logic_error("CRC step not invertible");
      low_of_high[high] = static_cast<int>(i);
    }
    const auto inverse_step = [&low_of_high](std::uint16_t a) {
      const auto low = static_cast<unsigned>(low_of_high[a >> 8U]);
      const unsigned high = (a ^ crc_detail::kTable[low]) & 0xFFU;
      return static_cast<std::uint16_t>((high << 8U) | low);
    };
    for (unsigned b = 0; b < 256; ++b) step[0][b] = crc_detail::kTable[b];
    for (std::size_t j = 1; j <= kBlock; ++j) {
      for (unsigned b = 0; b < 256; ++b) step[j][b] = inverse_step(step[j - 1][b]);
    }
    initial[0] = kCrcInit;
    for (std::size_t o = 1; o < kBlock; ++o) initial[o] = inverse_step(initial[o - 1]);
    for (unsigned x = 0; x < 256; ++x) {
      auto low = static_cast<std::uint16_t>(x);
      auto high = static_cast<std::uint16_t>(x << 8U);
      for (std::size_t k = 0; k < kBlock; ++k) {  // A: the register's step over a zero byte
        low = crc16_update(low, 0);
        high = crc16_update(high, 0);
      }
      to_next_low[x] = low;
      to_next_high[x] = high;
    }
  }
};

const Tables& tables() {
  static const Tables built;
  return built;
}

// A target to a block's base, its end's value taken out: to the next block's base.
std::uint16_t to_next_block(const Tables& t, std::uint16_t moved) {
  return t.to_next_low[moved & 0xFFU] ^ t.to_next_high[moved >> 8U];
}

}  // namespace

void CrcZeroIndex::reach(std::uint64_t to, const std::uint8_t* window, std::uint64_t window_start) {
  if (origin_ == kNone || computed_ < window_start) {
    // Bytes left the window before they were looked at: a new chain of blocks from here.
    origin_ = window_start;
    computed_ = window_start;
    value_[computed_ % kReach] = 0;
  }
  if (computed_ >= to) return;
  const Tables& t = tables();
  std::uint64_t position = computed_;
  std::uint16_t value = value_[position % kReach];
  std::size_t offset = (position - origin_) % kBlock;
  while (position < to) {
    const std::uint8_t byte = window[position - window_start];
    ++position;
    ++offset;
    value ^= t.step[offset][byte];
    if (offset == kBlock) {
      // The block's end: its value to this base is kept, and a new block starts at zero.
      block_end_[((position - origin_) / kBlock - 1) % kEnds] = value;
      value = 0;
      offset = 0;
    }
    value_[position % kReach] = value;
    earlier_[position % kReach] = latest_[value % kBuckets];
    latest_[value % kBuckets] = position;
  }
  computed_ = position;
}

void CrcZeroIndex::note_matches(CrcScan& scan, std::uint16_t target, std::uint64_t from,
                                std::uint64_t to) const {
  if (to - from < kCompareUpTo) {
    // A search extended by a few bytes (per-byte reads extend each search by one): a few
    // comparisons cost less than a walk that starts with a look-up in the buckets.
    for (std::uint64_t position = from; position <= to; ++position) {
      if (value_[position % kReach] == target) {
        scan.note_zero(static_cast<std::size_t>(position - scan.start));
      }
    }
    return;
  }
  // Newest first: skip those past `to`, note those down to `from` that hold the target (the
  // bucket holds other values too). A position older than the window (or none: kNone) ends
  // the chain.
  for (std::uint64_t position = latest_[target % kBuckets];
       position != kNone && position >= from && position >= window_start_;
       position = earlier_[position % kReach]) {
    if (position <= to && value_[position % kReach] == target) {
      scan.note_zero(static_cast<std::size_t>(position - scan.start));
    }
  }
}

CrcZeroIndex::CrcZeroIndex() : initial_(tables().initial.data()) {}

void CrcZeroIndex::span_values(std::span<const std::uint8_t> bytes, std::uint16_t* values,
                               std::uint16_t* targets) {
  if (bytes.size() > kBlock) throw std::logic_error("CRC span values beyond one block");
  const Tables& t = tables();
  std::uint16_t value = 0;
  values[0] = 0;
  for (std::size_t q = 1; q <= bytes.size(); ++q) {
    targets[q - 1] = value ^ t.initial[q - 1];
    value ^= t.step[q][bytes[q - 1]];
    values[q] = value;
  }
}

std::uint16_t CrcZeroIndex::moved_on(std::uint16_t target, std::uint64_t block) const {
  return to_next_block(tables(), target ^ block_end_[block % kEnds]);
}

void CrcZeroIndex::note_zeros(CrcScan& scan, std::size_t length, const std::uint8_t* window,
                              std::uint64_t window_start) {
  if (length <= scan.scanned) return;
  window_start_ = window_start;
  const std::uint64_t start = scan.start;
  reach(start + length, window, window_start);
  const Tables& t = tables();
  const std::size_t offset = (start - origin_) % kBlock;
  const std::uint16_t target = target_of(start);
  const std::size_t shortest = std::max<std::size_t>(scan.scanned + 1, kMinAdu);
  scan.scanned = static_cast<std::uint16_t>(length);
  if (shortest > length) return;
  // Lengths that end in the start's block, then those that end in the next one.
  const std::size_t in_block = std::min(length, kBlock - 1 - offset);
  if (shortest <= in_block) note_matches(scan, target, start + shortest, start + in_block);
  if (length <= in_block) return;
  const std::uint16_t next_target = to_next_block(t, target ^ block_end_[block_of(start) % kEnds]);
  note_matches(scan, next_target, start + std::max(shortest, in_block + 1), start + length);
}

}  // namespace rtu
