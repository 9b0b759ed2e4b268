#include "device_profile.hpp"

#include <algorithm>
#include <cmath>

#include "devices.hpp"

namespace rtu::sim {

std::optional<Bytes> DeviceProfile::answer_to_bad_crc(const Bytes& request) const {
  (void)request;
  return std::nullopt;
}

Nanos DeviceProfile::inter_char_gap(Rng& rng, const LineSettings& line) {
  (void)rng;
  (void)line;
  return 0;
}

double Drift::advance(Rng& rng) {
  value_ += (rng.unit() * 2.0 - 1.0) * step_;
  // Pull back towards the centre so the walk stays plausible over long captures.
  value_ = std::clamp(value_, centre_ - spread_, centre_ + spread_);
  return value_;
}

std::uint16_t to_u16(double v) {
  return static_cast<std::uint16_t>(std::clamp(std::lround(v), 0L, 65535L));
}

std::uint16_t to_s16_bits(double v) {
  const long s = std::clamp(std::lround(v), -32768L, 32767L);
  return static_cast<std::uint16_t>(s & 0xFFFF);
}

const std::vector<std::string>& device_names() {
  static const std::vector<std::string> names{"yw2050", "yw2300", "th900", "yakotec", "generic"};
  return names;
}

std::unique_ptr<DeviceProfile> make_device(std::string_view name) {
  if (name == "yw2050") return make_yw2050(1);
  if (name == "yw2300") return make_yw2300(2);
  if (name == "th900") return make_th900(3);
  if (name == "yakotec") return make_yakotec(4);
  if (name == "generic") return make_generic(17);
  return nullptr;
}

}  // namespace rtu::sim
