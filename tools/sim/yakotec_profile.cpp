// YAKOTEC stepper driver (shared device document YAKOTEC.md): FC03/06/10 only, 32-bit values
// HIGH word first, and vendor exception codes that differ from the standard ones. It even
// answers a request with a bad CRC, with its exception code 01.
#include "devices.hpp"

namespace rtu::sim {
namespace {

constexpr std::uint8_t kRead = 0x03;
constexpr std::uint8_t kWriteSingle = 0x06;
constexpr std::uint8_t kWriteMultiple = 0x10;

class Yakotec final : public DeviceProfile {
 public:
  using DeviceProfile::DeviceProfile;
  [[nodiscard]] std::string_view name() const override { return "yakotec"; }

  void poll_cycle(Rng& rng, std::vector<Exchange>& out) override {
    advance(rng);
    const std::uint8_t a = address();
    const auto pos = static_cast<std::uint32_t>(position_);
    out.push_back({read_request(a, kRead, 0x000A, 3),
                   registers_response(a, kRead,
                                      {static_cast<std::uint16_t>(pos >> 16U),
                                       static_cast<std::uint16_t>(pos & 0xFFFFU), speed_})});
    out.push_back({read_request(a, kRead, 0x0023, 1), registers_response(a, kRead, {max_speed_})});
    if (rng.chance(0.3)) {
      out.push_back({read_request(a, kRead, 0x001D, 3),
                     registers_response(a, kRead, {jog_speed_, 100, 100})});
    }
    if (rng.chance(0.05)) {
      // 0027 = 1 starts a position move, 2 a jog move.
      const Bytes req = write_single(a, kWriteSingle, 0x0027, rng.chance(0.5) ? 1 : 2);
      speed_ = max_speed_;
      out.push_back({req, req});
    }
    if (rng.chance(0.03)) {
      max_speed_ = static_cast<std::uint16_t>(rng.between(60, 300));
      const Bytes req = write_single(a, kWriteSingle, 0x0023, max_speed_);
      out.push_back({req, req});
    }
    if (rng.chance(0.03)) {
      const auto pulses = static_cast<std::uint32_t>(rng.between(1000, 200000));
      out.push_back({write_multiple_request(a, 0x0024,
                                            {static_cast<std::uint16_t>(pulses >> 16U),
                                             static_cast<std::uint16_t>(pulses & 0xFFFFU)}),
                     write_multiple_response(a, 0x0024, 2)});
    }
    if (rng.chance(0.02)) {
      jog_speed_ = static_cast<std::uint16_t>(rng.between(30, 120));
      out.push_back({write_multiple_request(a, 0x001D, {jog_speed_, 100, 100}),
                     write_multiple_response(a, 0x001D, 3)});
    }
  }

  // The vendor codes of the document, each with a request that provokes it.
  Exchange provoke_exception(Rng& rng) override {
    const std::uint8_t a = address();
    switch (rng.below(6)) {
      case 0:  // 02: function code not supported
        return {read_request(a, 0x02, 0x0000, 4), exception_response(a, 0x02, 0x02)};
      case 1:  // 03: register address out of range
        return {read_request(a, kRead, 0x003C, 1), exception_response(a, kRead, 0x03)};
      case 2:  // 04: write address out of range
        return {write_single(a, kWriteSingle, 0xFF00, 0xFFFF),
                exception_response(a, kWriteSingle, 0x04)};
      case 3:  // 05: too many registers in one request
        return {read_request(a, kRead, 0x0020, 0x20), exception_response(a, kRead, 0x05)};
      case 4:  // 06: write to a read-only address
        return {write_single(a, kWriteSingle, 0x0000, 0x0001),
                exception_response(a, kWriteSingle, 0x06)};
      default:  // 07: value out of range
        return {write_single(a, kWriteSingle, 0x0020, 0xFFFF),
                exception_response(a, kWriteSingle, 0x07)};
    }
  }

  [[nodiscard]] std::optional<Bytes> answer_to_bad_crc(const Bytes& request) const override {
    if (request.size() < 2 || request[0] != address()) return std::nullopt;
    return exception_response(address(), static_cast<std::uint8_t>(request[1] & 0x7FU), 0x01);
  }

  Bytes broadcast_write(Rng& rng) override {
    (void)rng;
    return write_multiple_request(0, 0x001D, {60, 100, 100});  // same jog profile everywhere
  }

  Nanos turnaround(Rng& rng) override { return rng.nanos(2 * kNanosPerMilli, 6 * kNanosPerMilli); }

 private:
  void advance(Rng& rng) {
    if (speed_ > 0) {
      position_ += static_cast<std::int64_t>(speed_) * rng.between(5, 15);
      if (rng.chance(0.1)) speed_ = 0;  // move finished
    }
  }

  std::int64_t position_ = 5000;  // as in the seed example
  std::uint16_t speed_ = 0;
  std::uint16_t max_speed_ = 60;
  std::uint16_t jog_speed_ = 60;
};

}  // namespace

std::unique_ptr<DeviceProfile> make_yakotec(std::uint8_t address) {
  return std::make_unique<Yakotec>(address);
}

}  // namespace rtu::sim
