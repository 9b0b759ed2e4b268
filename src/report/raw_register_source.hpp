#pragma once
// The PointSource for slaves with no device map: raw 16-bit register and single-bit values
// at their protocol addresses, named "holding 0x0032", "input 0x0032", "coil 0x0010",
// "discrete 0x0010". Read values come from normal responses to FC01-04 and FC23 (the request
// gives the start address); written values from the requests of FC05, FC06, FC15, FC16 and
// FC23, once their normal response confirms the write. Frames with a bad CRC or a byte count
// that does not fit are skipped: a value is reported only when the bytes are trustworthy.
#include <array>

#include "report/point_source.hpp"

namespace rtu {

class RawRegisterSource : public PointSource {
 public:
  void extract(const Record& frame, PointSink& sink) override;

 private:
  std::array<char, 32> name_{};
};

}  // namespace rtu
