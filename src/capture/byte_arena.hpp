#pragma once
// Bytes of many reads (and their line errors) copied into one growing buffer, to be handed
// to another thread in a batch: one allocation per batch, not one per read. Errors sit at
// the same positions as their bytes; a run without errors costs no error bytes unless a
// later run has some.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace rtu {

class ByteArena {
 public:
  // Where a run lies in the arena. 32 bits suffice: a batch ends once its arena holds a few
  // hundred KB, and no single read, line or record comes near 4 GB. Kept small because a
  // per-byte capture hands over one run per byte.
  struct Run {
    std::uint32_t at = 0;
    std::uint32_t size = 0;
    bool has_errors = false;
  };

  Run add(std::span<const std::uint8_t> bytes, std::span<const std::uint8_t> errors = {}) {
    Run run{static_cast<std::uint32_t>(size_), static_cast<std::uint32_t>(bytes.size()),
            !errors.empty()};
    make_room(bytes.size());
    if (bytes.size() == 1) {
      bytes_[size_] = bytes[0];  // a per-byte capture's every read: no call to copy one byte
    } else if (!bytes.empty()) {
      std::copy(bytes.begin(), bytes.end(), bytes_.begin() + static_cast<std::ptrdiff_t>(size_));
    }
    size_ += bytes.size();
    if (run.has_errors) {
      errors_.resize(size_, 0);  // earlier runs' places stay zero
      std::copy(errors.begin(), errors.end(),
                errors_.begin() + static_cast<std::ptrdiff_t>(run.at));
    }
    return run;
  }
  // Appends error-free bytes to `run`, which must be the last run added.
  void extend(Run& run, std::span<const std::uint8_t> bytes) {
    make_room(bytes.size());
    std::copy(bytes.begin(), bytes.end(), bytes_.begin() + static_cast<std::ptrdiff_t>(size_));
    size_ += bytes.size();
    run.size += static_cast<std::uint32_t>(bytes.size());
  }
  [[nodiscard]] std::span<const std::uint8_t> bytes(const Run& run) const {
    return {bytes_.data() + run.at, run.size};
  }
  // Empty for a run added without errors.
  [[nodiscard]] std::span<const std::uint8_t> errors(const Run& run) const {
    if (!run.has_errors) return {};
    return {errors_.data() + run.at, run.size};
  }
  [[nodiscard]] std::size_t size() const { return size_; }
  void clear() {
    size_ = 0;
    errors_.clear();
  }

 private:
  // bytes_ is kept longer than what it holds (size_), and grows by doubling: a byte is then
  // stored after one compare, where a push_back was a call.
  void make_room(std::size_t more) {
    if (bytes_.size() - size_ < more) [[unlikely]]
      grow(more);
  }
  [[gnu::noinline]] void grow(std::size_t more) {
    bytes_.resize(std::max({bytes_.size() * 2, size_ + more, std::size_t{4096}}));
  }
  std::vector<std::uint8_t> bytes_;
  std::size_t size_ = 0;
  std::vector<std::uint8_t> errors_;
};

}  // namespace rtu
