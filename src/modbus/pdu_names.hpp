#pragma once
// Names of the sub-codes inside some PDUs (MODBUS Application Protocol V1.1b3).
#include <cstdint>
#include <string_view>

namespace rtu {

// FC08 sub-function (§6.8.1): "Return Query Data"; "Reserved" for unassigned codes.
std::string_view diagnostics_sub_function_name(std::uint16_t sub_function);
// True for the sub-functions §6.8.1 assigns (00-04, 0A-12, 14).
bool is_known_diagnostics_sub_function(std::uint16_t sub_function);

// FC43 / MEI 0E object id (§6.21): "VendorName"; empty for reserved and private ids.
std::string_view device_id_object_name(std::uint8_t object_id);

// FC43 / MEI 0E read device id code: "basic", "regular", "extended", "specific"; empty else.
std::string_view read_device_id_code_name(std::uint8_t code);

}  // namespace rtu
