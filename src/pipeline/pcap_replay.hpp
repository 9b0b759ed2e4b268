#pragma once
// replay_capture for pcap/pcapng files (see capture/pcap_import.hpp for what the records
// mean). A file may hold raw chunks (250), frames (252), or both, as `rtuscope export --raw`
// writes them. Raw chunks are the fuller evidence (silences, line errors), so when a file
// has any, they are re-framed and its frame records are left aside; otherwise the frame
// records are decoded as they are: CRC-checked, classified and paired again, each frame's
// end estimated as its start plus its length in character times. A frame record longer
// than 256 bytes is split into frames and noise (see DecodePipeline::push_frame).
#include <string>

#include "framing/capture_info.hpp"
#include "framing/record.hpp"
#include "pipeline/replay.hpp"

namespace rtu {

CaptureInfo replay_pcap_capture(const std::string& path, const ReplayOptions& options,
                                RecordSink& sink);

}  // namespace rtu
