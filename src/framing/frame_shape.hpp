#pragma once
// Expected ADU lengths (address + PDU + CRC) for every public function code, in either
// role, computed from the bytes seen so far. The framer uses these where timestamps are too
// coarse to show frame gaps; each candidate is then confirmed by the CRC.
#include <cstdint>
#include <span>

#include "framing/record.hpp"

namespace rtu {

enum class ShapeStatus : std::uint8_t {
  kLength,         // the ADU is exactly `value` bytes long
  kNeedMore,       // `value` bytes must be seen before the length is known
  kUnpredictable,  // the function has no length rule here (vendor FCs, FC08/00, MEI 0D)
  kImpossible,     // the bytes cannot start a frame of this role
};

struct Shape {
  ShapeStatus status = ShapeStatus::kUnpredictable;
  std::uint16_t value = 0;

  static constexpr Shape length(std::size_t n) {
    return n > kMaxAdu ? Shape{ShapeStatus::kImpossible, 0}
                       : Shape{ShapeStatus::kLength, static_cast<std::uint16_t>(n)};
  }
  static constexpr Shape need(std::size_t n) {
    return Shape{ShapeStatus::kNeedMore, static_cast<std::uint16_t>(n)};
  }
  static constexpr Shape unpredictable() { return Shape{ShapeStatus::kUnpredictable, 0}; }
  static constexpr Shape impossible() { return Shape{ShapeStatus::kImpossible, 0}; }
  friend constexpr bool operator==(Shape, Shape) = default;
};

// `prefix` starts at the address byte. Role must be kRequest or kResponse.
Shape predict_shape(std::span<const std::uint8_t> prefix, Role role);

}  // namespace rtu
