#pragma once
// Where the Modbus CRC of a span of the byte stream comes out zero, for every start at once.
//
// The framer looks for frames of no known length by the CRC alone: from a start p, every
// length L (kMinAdu..kMaxAdu) at which the CRC of bytes [p, p+L) is zero. Run byte by byte,
// that is up to kMaxAdu dependent table steps per start, and on a stretch that forms no
// frame (noise, a sick bus, traffic read at the wrong baud rate) every byte is a start:
// the framer then spent nearly all its time in those steps, at about 2 MB/s of noise.
//
// The CRC is linear, which turns each search into comparisons. With A the CRC register's
// step over a zero byte (invertible) and P(q) the register after bytes [B, q) from zero,
// the register after [p, q) from the initial value I is A^(q-p) (I ^ P(p)) ^ P(q). It is
// zero exactly when
//     U(q) == U(p) ^ A^-(p-B) I,   where U(q) = A^-(q-B) P(q),
// and U(q) = U(q-1) ^ A^-(q-B) T[b] for the byte b before q (T: the CRC table). So one
// value per position, each computed once with one table look-up, answers the search from
// every start: the positions whose value is the start's target, looked up by value.
//
// The base B is a block start (every kBlock positions from the chain's origin); a start's
// search reaches at most one block further, where the target it compares with is moved to
// that block's base by one fixed linear step. Values are kept for the framer's whole window
// and computed only when a search asks, so traffic that the length rules frame costs
// nothing here.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "framing/crc_scan_cache.hpp"
#include "framing/record.hpp"

namespace rtu {

class CrcZeroIndex {
 public:
  // Positions (bytes of the stream) whose values are kept: the framer's window must be
  // shorter.
  static constexpr std::size_t kReach = 4096;
  // Positions per block. At least kMaxAdu: a search leaves its start's block for the next
  // one at most.
  static constexpr std::size_t kBlock = 256;

  // Notes in `scan` each length in (scan.scanned, length] (at least kMinAdu) at which the
  // CRC from scan.start is zero, and sets scan.scanned to `length`. `window` holds the
  // stream's bytes from position `window_start` on, up to at least scan.start + length;
  // window_start never moves back between calls, and scan.start is at or after it.
  CrcZeroIndex();

  void note_zeros(CrcScan& scan, std::size_t length, const std::uint8_t* window,
                  std::uint64_t window_start);

  // The values themselves, for what compares them position by position as the window
  // grows (QuietStarts' watches). compute_through() makes every position up to `to` hold
  // one, with `window` as in note_zeros(). The values and targets below belong to a chain
  // of blocks, which starts anew (another chain()) where bytes left the window before
  // they were looked at: a target of one chain means nothing in another.
  void compute_through(std::uint64_t to, const std::uint8_t* window, std::uint64_t window_start) {
    window_start_ = window_start;
    // Inline, the answer when there is nothing to compute: asked at every watch made.
    if (origin_ == kNone || computed_ < window_start || computed_ < to) {
      reach(to, window, window_start);
    }
  }
  [[nodiscard]] std::uint64_t chain() const { return origin_; }
  // Whether `position` holds a value of the current chain.
  [[nodiscard]] bool holds(std::uint64_t position) const {
    return origin_ != kNone && origin_ <= position && position <= computed_ &&
           computed_ - position < kReach;
  }
  // The block of a position it holds: values and targets are to that block's base.
  [[nodiscard]] std::uint64_t block_of(std::uint64_t position) const {
    return (position - origin_) / kBlock;
  }
  [[nodiscard]] std::uint16_t value_at(std::uint64_t position) const {
    return value_[position % kReach];
  }
  // The value at which the CRC from `start` (a position it holds) comes out zero, to the
  // start's block: the CRC of [start, q) is zero exactly where value_at(q) is this, for q
  // in that block.
  [[nodiscard]] std::uint16_t target_of(std::uint64_t start) const {
    return value_[start % kReach] ^ initial_[(start - origin_) % kBlock];
  }
  // A target to block `block`, moved to the next block's base (once that block's end was
  // computed): for q in the next block.
  [[nodiscard]] std::uint16_t moved_on(std::uint16_t target, std::uint64_t block) const;

  // The same values for one span of at most kBlock bytes, its start as the base, for what
  // asks of every start and end within it at once: values[q] for q in [0, size] and
  // targets[a] for a in [0, size). The CRC of [a, b) is zero exactly where values[b] is
  // targets[a]. One table look-up a byte.
  static void span_values(std::span<const std::uint8_t> bytes, std::uint16_t* values,
                          std::uint16_t* targets);

 private:
  static constexpr std::size_t kEnds = 32;  // blocks in reach, rounded up to a power of 2
  static constexpr std::uint64_t kNone = UINT64_MAX;
  static_assert(kBlock >= kMaxAdu);
  static_assert(kEnds * kBlock >= kReach + kBlock);

  // Computes the values up to position `to`.
  void reach(std::uint64_t to, const std::uint8_t* window, std::uint64_t window_start);

  // Notes the zeros at positions in [from, to], all in one block, whose value is `target`.
  void note_matches(CrcScan& scan, std::uint16_t target, std::uint64_t from,
                    std::uint64_t to) const;

  // A^-o I by offset o in a block: the initial register's term in a start's target.
  const std::uint16_t* initial_;
  std::uint64_t origin_ = kNone;               // the first block's start
  std::uint64_t computed_ = 0;                 // the last position with a value
  std::array<std::uint16_t, kReach> value_{};  // by position % kReach, to its block's base
  // The positions of the values, newest first, by the value's low bits (kBuckets of them,
  // about two per position held, and small enough to stay in the cache, where one bucket
  // per value missed it): the latest by bucket, and from each position (by position % kReach) the
  // one before it in the same bucket. A search looks up its target instead of comparing
  // every position it covers. Entries older than the window end a walk (a chain restarted,
  // or the ring moved on); none is ever cleared.
  static constexpr std::size_t kBuckets = 4096;
  std::array<std::uint64_t, kBuckets> latest_ = [] {
    std::array<std::uint64_t, kBuckets> none{};
    none.fill(kNone);
    return none;
  }();
  std::array<std::uint64_t, kReach> earlier_{};
  std::uint64_t window_start_ = 0;  // of the last call: older positions are gone
  // By block % kEnds: the value of the block's end (the next block's start) to its own
  // base, which moves a target from the block to the next.
  std::array<std::uint16_t, kEnds> block_end_{};
};

}  // namespace rtu
