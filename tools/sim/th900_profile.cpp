// TH900 temperature controller (shared device document TH900.md). Set-points ("type 3"
// points) are read and written as two registers, the value then 0000; PV/PV2/RH (F0-F2) and
// MV/MV1 (F3-F4) are single registers. The controller is slow to answer and feeds its UART
// byte by byte, leaving small silences (below t1.5) inside its responses.
#include <array>

#include "devices.hpp"

namespace rtu::sim {
namespace {

constexpr std::uint8_t kRead = 0x03;
constexpr std::uint8_t kWriteSingle = 0x06;

class Th900 final : public DeviceProfile {
 public:
  using DeviceProfile::DeviceProfile;
  [[nodiscard]] std::string_view name() const override { return "th900"; }

  void poll_cycle(Rng& rng, std::vector<Exchange>& out) override {
    advance(rng);
    const std::uint8_t a = address();
    out.push_back({read_request(a, kRead, 0x0000, 2), registers_response(a, kRead, {sv_, 0})});
    out.push_back({read_request(a, kRead, 0x00F0, 3),
                   registers_response(a, kRead,
                                      {to_u16(pv_.value() * 10.0), to_u16(pv2_.value() * 10.0),
                                       to_u16(rh_.value() * 10.0)})});
    if (rng.chance(0.5)) {
      out.push_back(
          {read_request(a, kRead, 0x00F3, 2),
           registers_response(a, kRead, {to_u16(mv_.value() * 10.0), to_u16(mv_.value() * 5.0)})});
    }
    if (rng.chance(0.2)) {
      out.push_back({read_request(a, kRead, 0x0008, 2), registers_response(a, kRead, {al1_, 0})});
    }
    if (rng.chance(0.04)) {
      sv_ = static_cast<std::uint16_t>(rng.between(500, 1200));  // 50.0 … 120.0 °C
      out.push_back(
          {write_multiple_request(a, 0x0000, {sv_, 0}), write_multiple_response(a, 0x0000, 2)});
    }
    if (rng.chance(0.03)) {
      manual_ = !manual_;  // M/A: 00H automatic, 40H manual
      const Bytes req = write_single(a, kWriteSingle, 0x00F5, manual_ ? 0x40 : 0x00);
      out.push_back({req, req});
    }
    if (rng.chance(0.02)) {
      const Bytes req = write_single(a, kWriteSingle, 0x0007, 1);  // start autotune
      out.push_back({req, req});
    }
  }

  Exchange provoke_exception(Rng& rng) override {
    const std::uint8_t a = address();
    switch (rng.below(3)) {
      case 0: return {read_request(a, 0x04, 0x00F0, 1), exception_response(a, 0x04, 0x01)};
      case 1: return {read_request(a, kRead, 0x0100, 2), exception_response(a, kRead, 0x02)};
      default:
        return {write_single(a, kWriteSingle, 0x005A, 0x00FF),  // no such input type
                exception_response(a, kWriteSingle, 0x03)};
    }
  }

  Bytes broadcast_write(Rng& rng) override {
    const auto sv = static_cast<std::uint16_t>(rng.between(500, 900));
    return write_multiple_request(0, 0x0000, {sv, 0});
  }

  Nanos turnaround(Rng& rng) override {
    return rng.nanos(15 * kNanosPerMilli, 30 * kNanosPerMilli);
  }

  Nanos inter_char_gap(Rng& rng, const LineSettings& line) override {
    if (!rng.chance(0.3)) return 0;
    return rng.nanos(0, line.char_time() * 2 / 5);
  }

 private:
  void advance(Rng& rng) {
    // The process value creeps towards the set-point.
    const double target = sv_ / 10.0;
    pv_ = Drift(pv_.value() + (target - pv_.value()) * 0.05, 80, 0.3);
    pv_.advance(rng);
    pv2_.advance(rng);
    rh_.advance(rng);
    mv_.advance(rng);
  }

  std::uint16_t sv_ = 700;  // 70.0, as in the seed example
  std::uint16_t al1_ = 850;
  bool manual_ = false;
  Drift pv_{65.0, 80, 0.3};
  Drift pv2_{40.0, 5, 0.2};
  Drift rh_{45.0, 15, 0.5};
  Drift mv_{35.0, 30, 2};
};

}  // namespace

std::unique_ptr<DeviceProfile> make_th900(std::uint8_t address) {
  return std::make_unique<Th900>(address);
}

}  // namespace rtu::sim
