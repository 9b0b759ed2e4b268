#pragma once
// Where reports get register values over time. A PointSource turns a frame into values of
// named points ("holding 0x0032" raw, or a device map's "Ua" in V once dissectors know the
// slave) and tells which device model a slave is. Reports and the CSV export consume
// PointSamples and do not care which source made them.
#include <cstdint>
#include <string_view>

#include "core/time.hpp"
#include "framing/record.hpp"

namespace rtu {

struct PointSample {
  Nanos t = 0;  // start of the frame that carried the value
  std::uint8_t slave = 0;
  std::string_view point;  // valid only during the call
  double value = 0.0;
  std::string_view unit;  // empty for raw values
};

class PointSink {
 public:
  virtual ~PointSink() = default;
  virtual void on_point(const PointSample& sample) = 0;
};

class PointSource {
 public:
  virtual ~PointSource() = default;
  // Delivers every value `frame` carries to `sink` (responses carry read values, with
  // frame.request set; confirmed writes carry written values). Called once per record, in
  // output order.
  virtual void extract(const Record& frame, PointSink& sink) = 0;
  // The device model of `slave` ("YW2050"), or empty when unknown.
  [[nodiscard]] virtual std::string_view device_model(std::uint8_t slave) const {
    (void)slave;
    return {};
  }
  // The device's own meaning of an exception code (a vendor table, e.g. YAKOTEC's 01 = CRC
  // error), or empty where the standard meaning applies.
  [[nodiscard]] virtual std::string_view device_exception_name(std::uint8_t slave,
                                                               std::uint8_t code) const {
    (void)slave;
    (void)code;
    return {};
  }
  // Whether that model was recognised from the traffic rather than configured by the user.
  [[nodiscard]] virtual bool device_model_identified(std::uint8_t slave) const {
    (void)slave;
    return false;
  }
};

}  // namespace rtu
