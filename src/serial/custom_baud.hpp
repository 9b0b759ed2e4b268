#pragma once
// Any baud rate, including non-standard ones, through termios2 / BOTHER (FORMATS §7.5).
// Kept in its own translation unit: <asm/termbits.h> clashes with <termios.h>.
#include <cstdint>
#include <optional>
#include <system_error>

namespace rtu {

// Sets input and output speed of `fd` to `baud` exactly. Returns the error of the ioctl.
std::error_code set_custom_baud(int fd, std::uint32_t baud);
// The output speed the driver really uses (it may round), or nullopt when unreadable.
std::optional<std::uint32_t> read_baud(int fd);

}  // namespace rtu
