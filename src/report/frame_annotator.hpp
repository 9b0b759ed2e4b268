#pragma once
// Hook through which device dissectors add meaning to frames after pairing: named and
// scaled registers, device-specific issues, vendor exception names. The text and JSONL
// writers call it for every frame; with no annotator the output is plain Modbus.
#include <fmt/format.h>

#include <cstdint>
#include <string_view>

#include "core/json_writer.hpp"
#include "framing/record.hpp"

namespace rtu {

class FrameAnnotator {
 public:
  virtual ~FrameAnnotator() = default;
  // Called once per frame in output order (requests before their responses; a response
  // has frame.request set). May add issues and update learned state (e.g. PT/CT ratios).
  virtual void annotate(Record& frame) = 0;
  // Adds keys to the frame's open JSON object (e.g. "device", "registers").
  virtual void write_json(JsonWriter& json, const Record& frame) const = 0;
  // Appends to the frame's text line (e.g. "  Ua=229.8 V Ia=4.93 A").
  virtual void append_text(fmt::memory_buffer& out, const Record& frame) const = 0;
  // A vendor's meaning of an exception code, or empty for the standard one.
  [[nodiscard]] virtual std::string_view exception_name(const Record& frame,
                                                        std::uint8_t code) const {
    (void)frame;
    (void)code;
    return {};
  }
};

}  // namespace rtu
