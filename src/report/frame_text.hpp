#pragma once
// Small renderings shared by the text and JSONL writers.
#include <string_view>

#include "framing/record.hpp"

namespace rtu {

std::string_view role_name(Role role);        // "request" | "response" | "unknown"
std::string_view role_short_name(Role role);  // "req" | "resp" | "?"

}  // namespace rtu
