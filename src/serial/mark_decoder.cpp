#include "serial/mark_decoder.hpp"

namespace rtu {

void MarkDecoder::decode(std::span<const std::uint8_t> raw, std::vector<std::uint8_t>& bytes,
                         std::vector<std::uint8_t>& errors) {
  for (const std::uint8_t b : raw) {
    switch (state_) {
      case State::kData:
        if (b == 0xFF) {
          state_ = State::kAfterFF;
        } else {
          bytes.push_back(b);
          errors.push_back(kLineOk);
        }
        break;
      case State::kAfterFF:
        if (b == 0xFF) {
          bytes.push_back(0xFF);
          errors.push_back(kLineOk);
          state_ = State::kData;
        } else if (b == 0x00) {
          state_ = State::kAfterFF00;
        } else {
          // n_tty never produces this; keep both bytes rather than lose one.
          bytes.push_back(0xFF);
          errors.push_back(kLineOk);
          bytes.push_back(b);
          errors.push_back(kLineOk);
          state_ = State::kData;
        }
        break;
      case State::kAfterFF00:
        bytes.push_back(b);
        errors.push_back(b == 0x00 ? static_cast<std::uint8_t>(kBreak) : error_flag_);
        state_ = State::kData;
        break;
    }
  }
}

}  // namespace rtu
