#pragma once
// A simulated slave: what the master polls it for, how it answers, and how fast. One
// profile per device model of the shared device documents, plus a generic device that
// exercises the public function codes those models lack. Profiles keep their own register
// state, so values change plausibly from one poll cycle to the next.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "adu.hpp"
#include "core/time.hpp"
#include "rng.hpp"
#include "serial/line_settings.hpp"

namespace rtu::sim {

// One request of the master and the device's correct answer to it.
struct Exchange {
  Bytes request;                  // complete ADU, CRC included
  std::optional<Bytes> response;  // complete ADU; nullopt when the device stays silent
};

class DeviceProfile {
 public:
  explicit DeviceProfile(std::uint8_t address) : address_(address) {}
  virtual ~DeviceProfile() = default;
  DeviceProfile(const DeviceProfile&) = delete;
  DeviceProfile& operator=(const DeviceProfile&) = delete;

  // Lowercase model name, as --devices takes it ("yw2050").
  [[nodiscard]] virtual std::string_view name() const = 0;
  [[nodiscard]] std::uint8_t address() const { return address_; }

  // Appends the exchanges of one poll cycle (reads, and now and then a write), advancing
  // the device's measured values.
  virtual void poll_cycle(Rng& rng, std::vector<Exchange>& out) = 0;
  // A request this device refuses, with the exception response it really sends.
  virtual Exchange provoke_exception(Rng& rng) = 0;
  // A write that makes sense for every device of this model at once, addressed to slave 0.
  virtual Bytes broadcast_write(Rng& rng) = 0;
  // What the device answers to a request whose CRC is wrong: nothing, for most devices.
  [[nodiscard]] virtual std::optional<Bytes> answer_to_bad_crc(const Bytes& request) const;

  // Silence from the end of a request to the start of the response.
  virtual Nanos turnaround(Rng& rng) = 0;
  // Silence the device leaves after a character of its own responses (slow firmware
  // feeding the UART byte by byte); always well below t1.5.
  virtual Nanos inter_char_gap(Rng& rng, const LineSettings& line);

 private:
  std::uint8_t address_;
};

// A value that wanders around a centre, as measurements do.
class Drift {
 public:
  Drift(double centre, double spread, double step)
      : centre_(centre), spread_(spread), step_(step), value_(centre) {}
  double advance(Rng& rng);
  [[nodiscard]] double value() const { return value_; }

 private:
  double centre_;
  double spread_;
  double step_;
  double value_;
};

std::uint16_t to_u16(double v);       // rounded, clamped to 0..65535
std::uint16_t to_s16_bits(double v);  // rounded, clamped to -32768..32767, two's complement

// Known model names, in the default polling order.
const std::vector<std::string>& device_names();
// Profile for a model name at its default address; null for an unknown name.
std::unique_ptr<DeviceProfile> make_device(std::string_view name);

}  // namespace rtu::sim
