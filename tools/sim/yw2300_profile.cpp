// YW2300 motor protector (shared device document YW2300.md): relay outputs (FC01/05),
// digital inputs (FC02), measurements and parameters (FC03/06/10); silent on CRC errors.
#include <array>

#include "devices.hpp"

namespace rtu::sim {
namespace {

constexpr std::uint8_t kReadCoils = 0x01;
constexpr std::uint8_t kReadInputs = 0x02;
constexpr std::uint8_t kRead = 0x03;
constexpr std::uint8_t kWriteCoil = 0x05;
constexpr std::uint8_t kWriteSingle = 0x06;
constexpr std::uint16_t kParamBase = 0x5450;
constexpr std::uint16_t kParamCount = 19;  // 5450..5462

class Yw2300 final : public DeviceProfile {
 public:
  using DeviceProfile::DeviceProfile;
  [[nodiscard]] std::string_view name() const override { return "yw2300"; }

  void poll_cycle(Rng& rng, std::vector<Exchange>& out) override {
    advance(rng);
    const std::uint8_t a = address();
    out.push_back(
        {read_request(a, kReadCoils, 0x0000, 3), bits_response(a, kReadCoils, outputs_, 3)});
    out.push_back(
        {read_request(a, kReadInputs, 0x0000, 7), bits_response(a, kReadInputs, inputs_, 7)});
    // UAB, UBC, UCA, IA, IB, IC at 0103..0108.
    std::array<std::uint16_t, 6> meas{};
    for (std::size_t p = 0; p < 3; ++p) {
      meas[p] = to_u16(volts_[p].value());
      meas[3 + p] = to_u16(amps_[p].value() * 100.0);  // 0.01 A, 50.00 A → 5000 as in the seed
    }
    out.push_back({read_request(a, kRead, 0x0103, 6), registers_response(a, kRead, meas)});
    out.push_back({read_request(a, kRead, 0x011A, 2),
                   registers_response(a, kRead, {mode_, static_cast<std::uint16_t>(outputs_)})});
    if (rng.chance(0.1)) {
      out.push_back(
          {read_request(a, kRead, kParamBase, kParamCount), registers_response(a, kRead, params_)});
    }
    if (rng.chance(0.04)) {
      const auto relay = static_cast<std::uint16_t>(rng.below(3));
      const bool on = rng.chance(0.5);
      outputs_ = on ? (outputs_ | (1U << relay)) : (outputs_ & ~(1U << relay));
      const Bytes req =
          write_single(a, kWriteCoil, relay, on ? std::uint16_t{0xFF00} : std::uint16_t{0});
      out.push_back({req, req});
    }
    if (rng.chance(0.03)) {
      params_[9] = static_cast<std::uint16_t>(rng.between(5, 30));  // 5459 STAR, start time s
      const Bytes req = write_single(a, kWriteSingle, 0x5459, params_[9]);
      out.push_back({req, req});
    }
    if (rng.chance(0.02)) {
      out.push_back({write_multiple_request(a, kParamBase, {params_[0], params_[1]}),
                     write_multiple_response(a, kParamBase, 2)});
    }
  }

  Exchange provoke_exception(Rng& rng) override {
    const std::uint8_t a = address();
    switch (rng.below(4)) {
      case 0: return {read_request(a, 0x04, 0x0103, 3), exception_response(a, 0x04, 0x01)};
      case 1: return {read_request(a, kRead, 0x2000, 4), exception_response(a, kRead, 0x02)};
      case 2:  // a coil value other than FF00 or 0000
        return {write_single(a, kWriteCoil, 0x0001, 0x1234),
                exception_response(a, kWriteCoil, 0x03)};
      default:  // rated current 0.0 A is out of range
        return {write_single(a, kWriteSingle, 0x5458, 0),
                exception_response(a, kWriteSingle, 0x03)};
    }
  }

  Bytes broadcast_write(Rng& rng) override {
    (void)rng;
    return write_single(0, kWriteCoil, 0x0000, 0x0000);  // every protector drops relay 1
  }

  Nanos turnaround(Rng& rng) override { return rng.nanos(3 * kNanosPerMilli, 10 * kNanosPerMilli); }

 private:
  void advance(Rng& rng) {
    for (auto& v : volts_) v.advance(rng);
    for (auto& i : amps_) i.advance(rng);
    if (rng.chance(0.05)) inputs_ ^= 1U << rng.below(7);
  }

  std::array<Drift, 3> volts_{Drift(398, 8, 1), Drift(401, 8, 1), Drift(399, 8, 1)};
  std::array<Drift, 3> amps_{Drift(50, 6, 0.5), Drift(50, 6, 0.5), Drift(50, 6, 0.5)};
  std::uint32_t outputs_ = 0b011;
  std::uint32_t inputs_ = 0b0011111;
  std::uint16_t mode_ = 2;
  std::array<std::uint16_t, kParamCount> params_{2,      3, 0, 120, 1, 0, 1,   380, 500, 10,
                                                 0xFFFF, 6, 1, 0,   1, 0, 115, 85,  100};
};

}  // namespace

std::unique_ptr<DeviceProfile> make_yw2300(std::uint8_t address) {
  return std::make_unique<Yw2300>(address);
}

}  // namespace rtu::sim
