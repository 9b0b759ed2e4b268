#pragma once
// Text hex capture: `# baud=… parity=… stop=…`, a `# rtusim …` provenance comment, then one
// line per chunk, `<t> <hex bytes>`, where t is the decimal seconds at which the chunk's
// last byte was available (its exact end for per-byte chunks).
#include <ostream>
#include <span>
#include <string_view>

#include "timeline.hpp"
#include "usb_adapter_model.hpp"

namespace rtu::sim {

void write_hex_capture(std::ostream& out, const LineSettings& line, std::string_view command,
                       std::span<const WireByte> bytes, std::span<const OutputChunk> chunks);

}  // namespace rtu::sim
