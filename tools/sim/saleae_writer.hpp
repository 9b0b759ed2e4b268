#pragma once
// Saleae Logic 2 data-table export of an Async Serial analyser (facts sheet §5.2): header
// `name,type,start_time,duration,"data"`, one row per byte with its start bit time and its
// duration in seconds, hex radix. Times are on the capture's clock, which starts at 0.
#include <ostream>
#include <span>

#include "timeline.hpp"

namespace rtu::sim {

void write_saleae_table(std::ostream& out, std::span<const WireByte> bytes);

}  // namespace rtu::sim
