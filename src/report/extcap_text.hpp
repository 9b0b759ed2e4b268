#pragma once
// What `rtuscope extcap` tells Wireshark about itself (Wireshark's extcap interface, see
// its doc/extcap.adoc): one line per item, a keyword then {key=value} groups.
//
//  * Interfaces: one per serial port, named "rtuscope" + the port's absolute path
//    ("rtuscope/dev/ttyUSB0"), so the capture call names the port itself; Wireshark turns
//    the name into preference names (extcap.rtuscope_dev_ttyusb0.baud).
//  * Link types: 252 (Upper PDU, the decoded frames, as `rtuscope export` writes them) and
//    250 (RTAC Serial, the raw reads and line events, as `rtuscope live -w` records them).
//  * Options: the line settings, the response timeout, a bus file, the link type. Their
//    `call` names are lowercase (an uppercase letter makes Wireshark abort). Wireshark passes
//    a selector's default only sometimes, so each selector's default is "auto", which means
//    "not given": the bus file's setting, else Modbus's default, as for `rtuscope live`.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rtu::extcap {

inline constexpr std::string_view kInterfacePrefix = "rtuscope";
inline constexpr std::string_view kAuto = "auto";          // a selector left at its default
inline constexpr std::string_view kLinkFrames = "frames";  // --link-type values
inline constexpr std::string_view kLinkRaw = "raw";

// "/dev/ttyUSB0" → "rtuscope/dev/ttyUSB0". `port` must be an absolute path.
[[nodiscard]] std::string interface_for_port(std::string_view port);
// The inverse; nullopt when `interface` is not one of ours.
[[nodiscard]] std::optional<std::string> port_for_interface(std::string_view interface);

// --extcap-interfaces: the extcap line, then one interface line per port.
[[nodiscard]] std::string interfaces_text(const std::vector<std::string>& ports,
                                          std::string_view version);
// --extcap-dlts: the link types an interface can deliver.
[[nodiscard]] std::string dlts_text();
// --extcap-config: the options of an interface (the same for every port).
[[nodiscard]] std::string config_text();

}  // namespace rtu::extcap
