#pragma once
// Which serial ports this machine has, for lists a user picks from (Wireshark's interface
// list): the stable names in /dev/serial/by-id first, then /dev/ttyUSB*, /dev/ttyACM* and
// /dev/ttyS* that are not already listed under a by-id name. A port is listed only when it
// opens as a terminal and, for the on-board /dev/ttyS* (the kernel creates many that have
// no UART behind them), when the driver knows a UART type for it.
#include <string>
#include <string_view>
#include <vector>

namespace rtu {

// `dev` is the device folder (tests pass a fake one); the order is stable: by-id names
// sorted, then each family in numeric order (ttyS2 before ttyS10).
[[nodiscard]] std::vector<std::string> find_serial_ports(const std::string& dev = "/dev");

// "a:b::c" → {"a", "b", "c"}: a colon-separated list of paths, empty entries skipped.
[[nodiscard]] std::vector<std::string> split_port_list(std::string_view text);

}  // namespace rtu
