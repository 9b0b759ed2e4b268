#include "modbus/pdu_names.hpp"

namespace rtu {

std::string_view diagnostics_sub_function_name(std::uint16_t sub_function) {
  switch (sub_function) {
    case 0x00: return "Return Query Data";
    case 0x01: return "Restart Communications Option";
    case 0x02: return "Return Diagnostic Register";
    case 0x03: return "Change ASCII Input Delimiter";
    case 0x04: return "Force Listen Only Mode";
    case 0x0A: return "Clear Counters and Diagnostic Register";
    case 0x0B: return "Return Bus Message Count";
    case 0x0C: return "Return Bus Communication Error Count";
    case 0x0D: return "Return Bus Exception Error Count";
    case 0x0E: return "Return Server Message Count";
    case 0x0F: return "Return Server No Response Count";
    case 0x10: return "Return Server NAK Count";
    case 0x11: return "Return Server Busy Count";
    case 0x12: return "Return Bus Character Overrun Count";
    case 0x14: return "Clear Overrun Counter and Flag";
    default: return "Reserved";
  }
}

bool is_known_diagnostics_sub_function(std::uint16_t sub_function) {
  return sub_function <= 0x04 || (sub_function >= 0x0A && sub_function <= 0x12) ||
         sub_function == 0x14;
}

std::string_view device_id_object_name(std::uint8_t object_id) {
  switch (object_id) {
    case 0x00: return "VendorName";
    case 0x01: return "ProductCode";
    case 0x02: return "MajorMinorRevision";
    case 0x03: return "VendorUrl";
    case 0x04: return "ProductName";
    case 0x05: return "ModelName";
    case 0x06: return "UserApplicationName";
    default: return {};
  }
}

std::string_view read_device_id_code_name(std::uint8_t code) {
  switch (code) {
    case 0x01: return "basic";
    case 0x02: return "regular";
    case 0x03: return "extended";
    case 0x04: return "specific";
    default: return {};
  }
}

}  // namespace rtu
