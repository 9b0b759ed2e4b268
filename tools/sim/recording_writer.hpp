#pragma once
// The host's reads as `rtuscope live -w` records them: a pcapng file with one
// LINKTYPE_RTAC_SERIAL interface (ns timestamps) and one DATA_RX_START record per read,
// stamped with the read's completion. It is the input the speed targets name ("the native
// pcapng of a live recording"), made without waiting for a real bus.
//
// Unlike a live recording it declares no timing resolution or response timeout and has no
// CAPTURE_COMPLETE at its end, so a replay finds the timing from the reads themselves, as
// it does for the --out text hex of the same run: both decode to the same records.
#include <span>
#include <string>

#include "serial/line_settings.hpp"
#include "timeline.hpp"
#include "usb_adapter_model.hpp"

namespace rtu::sim {

// Throws InputError naming `path` when it cannot be created, OutputError when a write fails.
void write_read_recording(const std::string& path, const LineSettings& line,
                          std::span<const WireByte> bytes, std::span<const OutputChunk> chunks);

}  // namespace rtu::sim
