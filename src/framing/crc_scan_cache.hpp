#pragma once
// What the framer's CRC search for a frame of no known length has found so far, per start
// position, so that each new read extends the search instead of repeating it.
//
// The search from a start covers up to kMaxAdu bytes or the bytes up to the first silence
// the timestamps show, and notes each length at which the CRC comes out 0: by running the
// CRC on where a few bytes extend it, else by looking the zeros up (CrcZeroIndex). None of
// that depends on anything but the bytes, their silences and the timing resolution, which
// never change for a byte once it is buffered; so a scan is kept under its absolute start
// position and the resolution it was made with, and whatever asks about the same start
// later resumes it. What the zero lengths mean (a frame ends there if a silence or a
// further frame follows) depends on the bytes after them and is decided again each time.
//
// Without this, a buffered frame with no length rule is rescanned from its first byte on
// every read until it is decided: quadratic in its length, 40x slower on traffic of
// vendor function codes than on ordinary polling.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>

#include "core/crc16.hpp"
#include "core/time.hpp"
#include "framing/record.hpp"

namespace rtu {

struct CrcScan {
  static constexpr std::uint64_t kNoStart = UINT64_MAX;
  static constexpr std::size_t kWords = (kMaxAdu + 64) / 64;

  std::uint64_t start = kNoStart;  // absolute position of the first byte
  Nanos resolution = 0;            // the timing resolution the silences were judged with
  std::uint16_t scanned = 0;       // bytes the search covers so far
  std::uint16_t crc = kCrcInit;    // CRC of those bytes, while crc_known
  bool crc_known = true;           // false once CrcZeroIndex extended the search
  bool ended_at_silence = false;   // a silence follows byte `scanned`: the scan is complete
  bool found_zero = false;         // some bit of zero_lengths is set
  std::array<std::uint64_t, kWords> zero_lengths{};  // bit L: CRC is 0 after L bytes

  void note_zero(std::size_t length) {
    zero_lengths[length / 64] |= std::uint64_t{1} << (length % 64);
    found_zero = true;
  }

  // How many of `count` more bytes the search, its CRC known, runs on over before one
  // brings a zero that counts (at kMinAdu bytes or more).
  [[nodiscard]] std::size_t steps_without_zero(const std::uint8_t* bytes, std::size_t count) const {
    std::uint16_t c = crc;
    for (std::size_t k = 0; k < count; ++k) {
      c = crc16_update(c, bytes[k]);
      if (c == 0 && scanned + k + 1 >= kMinAdu) return k;
    }
    return count;
  }
  // The search, its CRC known, run on over `count` more bytes that bring no zero.
  void run_on(const std::uint8_t* bytes, std::size_t count) {
    for (std::size_t k = 0; k < count; ++k) crc = crc16_update(crc, bytes[k]);
    scanned = static_cast<std::uint16_t>(scanned + count);
  }

  // Calls f(length) for each zero length in ascending order until f returns true;
  // returns whether one did.
  template <typename F>
  bool any_zero_length(F&& f) const {
    for (std::size_t w = 0; w < kWords; ++w) {
      std::uint64_t bits = zero_lengths[w];
      while (bits != 0) {
        const auto bit = static_cast<std::size_t>(std::countr_zero(bits));
        if (f(w * 64 + bit)) return true;
        bits &= bits - 1;
      }
    }
    return false;
  }
};

// One scan per start the framer may hold undecided (kMaxPending = 4 * kMaxAdu).
// Direct-mapped on the start position; a collision only costs a rescan.
class CrcScanCache {
 public:
  // The scan for `start` made with `resolution`, or a fresh one in its place.
  // The scan kept for `start` with `resolution`, or nullptr.
  [[nodiscard]] const CrcScan* find(std::uint64_t start, Nanos resolution) const {
    const CrcScan& scan = slots_[start % kSlots];
    return scan.start == start && scan.resolution == resolution ? &scan : nullptr;
  }
  CrcScan& at(std::uint64_t start, Nanos resolution) {
    CrcScan& scan = slots_[start % kSlots];
    if (scan.start != start || scan.resolution != resolution) {
      scan = CrcScan{};
      scan.start = start;
      scan.resolution = resolution;
    }
    return scan;
  }

 private:
  static constexpr std::size_t kSlots = 1024;  // the most bytes the framer holds undecided
  std::array<CrcScan, kSlots> slots_{};
};

}  // namespace rtu
