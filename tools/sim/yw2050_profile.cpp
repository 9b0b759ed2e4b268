// YW2050 three-phase power meter (shared device document YW2050.md).
// Quirks reproduced: byte addressing (a read of n registers at A returns the values at
// A, A+2, …), 32-bit energy and PT/CT LOW word first, the same address meaning different
// things under FC03, FC06 and FC10, and silence on a CRC error.
#include <array>

#include "devices.hpp"

namespace rtu::sim {
namespace {

constexpr std::uint8_t kRead = 0x03;
constexpr std::uint8_t kWriteSingle = 0x06;
constexpr std::uint16_t kPt = 1;
constexpr std::uint16_t kCt = 40;  // a 200/5 A current transformer

class Yw2050 final : public DeviceProfile {
 public:
  using DeviceProfile::DeviceProfile;
  [[nodiscard]] std::string_view name() const override { return "yw2050"; }

  void poll_cycle(Rng& rng, std::vector<Exchange>& out) override {
    advance(rng);
    const std::uint8_t a = address();
    // Basic data 0000..003E: 32 values of the three phases and the totals.
    const std::array<std::uint16_t, 32> basic = basic_data();
    out.push_back({read_request(a, kRead, 0x0000, 32), registers_response(a, kRead, basic)});
    // Uav, Iav, F at 0032/0034/0036 (the seed's own example read).
    out.push_back({read_request(a, kRead, 0x0032, 3),
                   registers_response(a, kRead, {basic[25], basic[26], basic[27]})});
    if (rng.chance(0.5)) {
      const auto wh = static_cast<std::uint32_t>(energy_wh_);
      const auto varh = static_cast<std::uint32_t>(energy_varh_);
      out.push_back(
          {read_request(a, kRead, 0x0042, 8),
           registers_response(a, kRead, {low(wh), high(wh), 0, 0, low(varh), high(varh), 0, 0})});
    }
    if (rng.chance(0.15)) {
      out.push_back({read_request(a, kRead, 0x030E, 2), registers_response(a, kRead, {kPt, 0})});
      out.push_back({read_request(a, kRead, 0x0312, 2), registers_response(a, kRead, {kCt, 0})});
    }
    if (rng.chance(0.04)) {
      // FC06 0026 is the display language here, not a measurement (quirk 2).
      const Bytes req = write_single(a, kWriteSingle, 0x0026, 1);
      out.push_back({req, req});
    }
    if (rng.chance(0.03)) {
      const Bytes req = write_single(a, kWriteSingle, 0x0002, 0);  // wiring 3P4W
      out.push_back({req, req});
    }
    if (rng.chance(0.03)) {
      // FC10 0000..0003 is PT and 0004..0007 CT, low word first (seed example: 0064 0000).
      out.push_back(
          {write_multiple_request(a, 0x0000, {kPt, 0}), write_multiple_response(a, 0x0000, 2)});
      out.push_back(
          {write_multiple_request(a, 0x0004, {kCt, 0}), write_multiple_response(a, 0x0004, 2)});
    }
  }

  Exchange provoke_exception(Rng& rng) override {
    const std::uint8_t a = address();
    switch (rng.below(4)) {
      case 0: return {read_request(a, 0x04, 0x0000, 2), exception_response(a, 0x04, 0x01)};
      case 1: return {read_request(a, kRead, 0x0200, 2), exception_response(a, kRead, 0x02)};
      case 2:  // more than the 125 registers one read may ask for
        return {read_request(a, kRead, 0x0000, 126), exception_response(a, kRead, 0x03)};
      default:  // slave address 0 is not a valid setting (1-247)
        return {write_single(a, kWriteSingle, 0x0000, 0),
                exception_response(a, kWriteSingle, 0x03)};
    }
  }

  Bytes broadcast_write(Rng& rng) override {
    if (rng.chance(0.5)) return write_single(0, kWriteSingle, 0x0026, 1);
    return write_multiple_request(0, 0x0004, {kCt, 0});
  }

  Nanos turnaround(Rng& rng) override { return rng.nanos(5 * kNanosPerMilli, 15 * kNanosPerMilli); }

 private:
  static std::uint16_t low(std::uint32_t v) { return static_cast<std::uint16_t>(v & 0xFFFFU); }
  static std::uint16_t high(std::uint32_t v) { return static_cast<std::uint16_t>(v >> 16U); }

  void advance(Rng& rng) {
    for (auto& u : phase_volts_) u.advance(rng);
    for (auto& i : phase_amps_) i.advance(rng);
    pf_.advance(rng);
    hz_.advance(rng);
    double kw = 0;
    for (std::size_t p = 0; p < 3; ++p) kw += phase_volts_[p].value() * phase_amps_[p].value();
    // Energy accumulates a few Wh per poll cycle at these loads.
    energy_wh_ += kw * pf_.value() / 1000.0 + 0.5;
    energy_varh_ += kw * 0.3 / 1000.0 + 0.2;
  }

  // Raw register values (Rx) per the FC03 formulas with PT = 1, CT = 40.
  [[nodiscard]] std::array<std::uint16_t, 32> basic_data() const {
    std::array<std::uint16_t, 32> r{};
    const double pt_ct = kPt * kCt;
    double p_sum = 0;
    double q_sum = 0;
    double s_sum = 0;
    for (std::size_t p = 0; p < 3; ++p) {
      const double u = phase_volts_[p].value();
      const double i = phase_amps_[p].value();
      const double s = u * i;
      const double pw = s * pf_.value();
      const double q = s * 0.31;
      p_sum += pw;
      q_sum += q;
      s_sum += s;
      const std::size_t base = p * 8;  // 0x10 bytes per phase = 8 registers
      r[base + 0] = to_u16(u / (kPt * 0.01));
      r[base + 1] = to_u16(u * 1.732 / (kPt * 0.01));
      r[base + 2] = to_u16(i / (kCt * 0.0001));
      r[base + 3] = 0;
      r[base + 4] = to_s16_bits(pw / (pt_ct * 0.4));
      r[base + 5] = to_s16_bits(pf_.value() * 10000.0);
      r[base + 6] = to_s16_bits(q / (pt_ct * 0.4));
      r[base + 7] = to_u16(s / (pt_ct * 0.2));
    }
    double u_av = 0;
    double i_av = 0;
    for (std::size_t p = 0; p < 3; ++p) {
      u_av += phase_volts_[p].value() / 3.0;
      i_av += phase_amps_[p].value() / 3.0;
    }
    r[24] = to_u16(0.4 / (kCt * 0.0001));  // I0, a small zero-sequence current
    r[25] = to_u16(u_av / (kPt * 0.01));
    r[26] = to_u16(i_av / (kCt * 0.0001));
    r[27] = to_u16(hz_.value() / 0.00106813);
    r[28] = to_s16_bits(p_sum / (pt_ct * 0.4));
    r[29] = to_s16_bits(pf_.value() * 10000.0);
    r[30] = to_s16_bits(q_sum / (pt_ct * 0.4));
    r[31] = to_u16(s_sum / (pt_ct * 0.2));
    return r;
  }

  std::array<Drift, 3> phase_volts_{Drift(230, 6, 0.8), Drift(229, 6, 0.8), Drift(231, 6, 0.8)};
  std::array<Drift, 3> phase_amps_{Drift(95, 40, 4), Drift(102, 40, 4), Drift(88, 40, 4)};
  Drift pf_{0.93, 0.05, 0.01};
  Drift hz_{50.0, 0.08, 0.01};
  double energy_wh_ = 1'234'567;
  double energy_varh_ = 345'678;
};

}  // namespace

std::unique_ptr<DeviceProfile> make_yw2050(std::uint8_t address) {
  return std::make_unique<Yw2050>(address);
}

}  // namespace rtu::sim
