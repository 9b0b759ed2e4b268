#pragma once
// Whether a span of bytes holds two CRC-valid spans back to back: frames, one after the
// other, rather than one frame.
//
// A frame of no length rule (a vendor function code) is known only by its CRC, and where it
// ends by what follows: a silence, the capture's end, or (where an adapter's timer hides the
// silences) a chain of further CRC zeros. Damage breaks that: the search for the next frame
// then tries a start at every byte of the damaged one, and from each the CRC comes out zero
// by chance (1 in 65,536) where any of the real frames within reach ends, and what follows
// those real frames confirms it. On a vendor bus behind a 16 ms adapter with one frame in twenty
// damaged, about one damaged frame in fifty swallowed a run of real frames that way into
// one "CRC-valid" frame (tools/accuracy/vendor_bus.py --faults 0.05).
//
// A real frame of n bytes holds two such spans by chance in some n^3/6 ways of 1 in
// 65,536^2 each: about 1 in 300,000 frames of 43 bytes, 1 in 1,500 of the longest (256).
#include <cstdint>
#include <span>

namespace rtu {

// Each of the two spans at least kMinAdu bytes, anywhere in `bytes` (the whole counts as
// neither: a span ending at its end and one starting at its start may both be the whole).
bool holds_crc_chain(std::span<const std::uint8_t> bytes);

}  // namespace rtu
