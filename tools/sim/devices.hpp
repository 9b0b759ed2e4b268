#pragma once
// Factories of the concrete device profiles (one file each).
#include <cstdint>
#include <memory>

#include "device_profile.hpp"

namespace rtu::sim {

std::unique_ptr<DeviceProfile> make_yw2050(std::uint8_t address);   // power meter
std::unique_ptr<DeviceProfile> make_yw2300(std::uint8_t address);   // motor protector
std::unique_ptr<DeviceProfile> make_th900(std::uint8_t address);    // temperature controller
std::unique_ptr<DeviceProfile> make_yakotec(std::uint8_t address);  // stepper driver
// Not a documented model: a conforming device answering the other public function codes
// (FC07, 08, 0B, 0F, 11, 14, 16, 17, 18, 2B/0E) and one vendor code (0x41), so decoders meet
// them on a realistic bus.
std::unique_ptr<DeviceProfile> make_generic(std::uint8_t address);

}  // namespace rtu::sim
