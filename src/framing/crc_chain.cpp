#include "framing/crc_chain.hpp"

#include <algorithm>
#include <array>
#include <bitset>

#include "framing/crc_zero_index.hpp"
#include "framing/record.hpp"

namespace rtu {

namespace {

// A set of 16-bit values, emptied by taking out what was put in: a span's check touches a
// few hundred of its 65,536 bits, so it never clears the rest.
class ValueSet {
 public:
  void insert(std::uint16_t value) {
    if (!bits_.test(value)) inserted_[count_++] = value;
    bits_.set(value);
  }
  [[nodiscard]] bool contains(std::uint16_t value) const { return bits_.test(value); }
  void clear() {
    for (std::size_t i = 0; i < count_; ++i) bits_.reset(inserted_[i]);
    count_ = 0;
  }

 private:
  std::bitset<65536> bits_;
  std::array<std::uint16_t, kMaxAdu + 1> inserted_{};
  std::size_t count_ = 0;
};

}  // namespace

bool holds_crc_chain(std::span<const std::uint8_t> bytes) {
  const std::size_t n = std::min(bytes.size(), kMaxAdu);
  if (n < 2 * kMinAdu) return false;
  // The CRC of [a, b) is zero where values[b] == targets[a] (CrcZeroIndex): a chain is a
  // boundary b with a valid span ending there and one starting there. Each side is one
  // sweep that keeps the values seen so far, so the check is linear in the span rather
  // than a CRC run from every start.
  std::array<std::uint16_t, kMaxAdu + 1> values{};
  std::array<std::uint16_t, kMaxAdu> targets{};
  CrcZeroIndex::span_values(bytes.first(n), values.data(), targets.data());
  thread_local ValueSet seen;
  // Boundaries at which a span of at least kMinAdu bytes ends valid. In a real frame there
  // are rarely any, and then the other side is not asked.
  std::bitset<kMaxAdu + 1> ends_one;
  for (std::size_t b = kMinAdu; b + kMinAdu <= n; ++b) {
    seen.insert(targets[b - kMinAdu]);
    if (seen.contains(values[b])) ends_one.set(b);
  }
  seen.clear();
  if (ends_one.none()) return false;
  bool chain = false;
  for (std::size_t b = n - kMinAdu + 1; b-- > kMinAdu && !chain;) {
    seen.insert(values[b + kMinAdu]);
    chain = ends_one.test(b) && seen.contains(targets[b]);
  }
  seen.clear();
  return chain;
}

}  // namespace rtu
