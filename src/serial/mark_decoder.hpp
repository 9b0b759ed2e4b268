#pragma once
// Decodes the in-band error marks the Linux tty layer inserts with PARMRK set
// (kernel n_tty.c; FORMATS §7.1):
//   FF FF    → data byte FF
//   FF 00 x  → byte x received with a parity or framing error
//   FF 00 00 → break (delivered as a 00 byte flagged kBreak, as UART drivers do)
// In-band marks cannot tell parity from framing errors, nor a break from an error on a
// 00 byte; the caller refines them with the driver's counters where it has them.
// A mark may be split across read() calls: the decoder keeps its state between calls.
#include <cstdint>
#include <span>
#include <vector>

#include "core/chunk.hpp"

namespace rtu {

class MarkDecoder {
 public:
  // `error_flag`: the LineError given to `FF 00 x` marks (kParityError on lines with
  // parity, where that is by far the likelier cause; kFramingError otherwise).
  explicit MarkDecoder(std::uint8_t error_flag = kParityError) : error_flag_(error_flag) {}

  // Appends the decoded bytes of `raw` to `bytes` and their flags to `errors` (one per
  // byte). Bytes of an unfinished mark at the end of `raw` are held for the next call.
  void decode(std::span<const std::uint8_t> raw, std::vector<std::uint8_t>& bytes,
              std::vector<std::uint8_t>& errors);
  // Bytes of a mark still waiting for its end.
  [[nodiscard]] bool pending() const { return state_ != State::kData; }
  void reset() { state_ = State::kData; }

 private:
  enum class State : std::uint8_t { kData, kAfterFF, kAfterFF00 };
  std::uint8_t error_flag_;
  State state_ = State::kData;
};

}  // namespace rtu
