#pragma once
// The host's reads as `rtuscope live -w` records them: a pcapng file with one
// LINKTYPE_RTAC_SERIAL interface (ns timestamps) and one DATA_RX_START record per read,
// stamped with the read's completion, its interface declaring the line and the timing
// resolution as a live run does (a replay reads such a file once, taking both from it). It
// is the input the speed targets name ("the native pcapng of a live recording"), made
// without waiting for a real bus.
//
// Unlike a live recording it declares no response timeout (what the user gave `live`, not a
// fact of the bus) and has no CAPTURE_COMPLETE at its end, so it decodes exactly as the --out
// text hex of the same run when both are given the resolution (--resolution-ms; without it,
// a declared resolution may still be raised by what the frames show, and the text hex's is
// estimated).
#include <span>
#include <string>

#include "serial/line_settings.hpp"
#include "timeline.hpp"
#include "usb_adapter_model.hpp"

namespace rtu::sim {

// Throws InputError naming `path` when it cannot be created, OutputError when a write fails.
// `resolution`: the smallest silence the reads' times show (a USB adapter's latency timer).
void write_read_recording(const std::string& path, const LineSettings& line, Nanos resolution,
                          std::span<const WireByte> bytes, std::span<const OutputChunk> chunks);

}  // namespace rtu::sim
