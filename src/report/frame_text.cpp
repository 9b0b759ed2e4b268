#include "report/frame_text.hpp"

namespace rtu {

std::string_view role_name(Role role) {
  switch (role) {
    case Role::kRequest: return "request";
    case Role::kResponse: return "response";
    case Role::kUnknown: return "unknown";
  }
  return "unknown";
}

std::string_view role_short_name(Role role) {
  switch (role) {
    case Role::kRequest: return "req";
    case Role::kResponse: return "resp";
    case Role::kUnknown: return "?";
  }
  return "?";
}

}  // namespace rtu
