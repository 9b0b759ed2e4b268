#pragma once
// How decoded points read, in text ("Ua=229.80 V") and in JSON lines
// ({"addr":0,"name":"Ua","raw":22980,"value":229.80,"unit":"V"}). One place, so that the
// two outputs say the same thing.
#include <fmt/format.h>

#include "core/json_writer.hpp"
#include "dissect/register_decoder.hpp"

namespace rtu::dissect {

// Appends "  name=value unit" for every point (two spaces before each).
void append_points_text(fmt::memory_buffer& out, const Decoded& decoded);
// Writes the "registers" array.
void write_points_json(JsonWriter& json, const Decoded& decoded);

}  // namespace rtu::dissect
