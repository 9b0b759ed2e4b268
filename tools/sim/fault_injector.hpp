#pragma once
// Which transactions go wrong, and how. In the classic profile a transaction gets at most
// one fault, with the configured probability, of a kind drawn uniformly from the enabled
// kinds. The heavy profile (a sick bus) gives a faulty transaction one or two faults and
// adds kinds the classic one lacks: damage anywhere in a frame, noise touching frames,
// lone glitch bytes right after a frame, early responses, absent slaves. The injector owns
// its own random stream, so the fault rate does not change the values the devices report,
// only what happens to their frames.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "adu.hpp"
#include "rng.hpp"
#include "serial/line_settings.hpp"

namespace rtu::sim {

enum class Fault : std::uint8_t {
  kCrc,         // one bit flipped in a request or a response (data or CRC byte)
  kNoise,       // a burst of random bytes while the bus is idle
  kTurnaround,  // 0x00 or 0xFF bytes while the line turns around (driver enable/release)
  kTruncated,   // the response stops short; the master then times out
  kTimeout,     // the slave does not answer
  kException,   // the master asks something the device refuses
  kPause,       // a silence between t1.5 and t3.5 inside a frame
  kShortGap,    // less than t3.5 of silence before a request or a response
  kBroadcast,   // a write to slave 0, which nobody answers
  kWrongSlave,  // the response carries another slave address than the request
  // Heavy profile only (not in all_faults(), so classic captures stay as they were).
  kBitflip,       // 1-3 bits flipped anywhere in a request or a response, address included
  kNoiseBefore,   // a burst that ends less than t3.5 before a request or a response
  kNoiseAfter,    // a burst that starts less than t3.5 after a request or a response
  kNoiseGap,      // a burst between request and response, less than t3.5 from both
  kGlitch,        // one byte of any value 50-150 us after the last frame (driver release)
  kFastResponse,  // the response starts 0.1 ms to 0.93 t1.5 after the request
  kDeadSlave,     // the master polls an address nobody has
};

enum class FaultProfile : std::uint8_t { kClassic, kHeavy };

// Command-line names ("crc", "noise", …), in the order above.
std::string_view fault_name(Fault f);
std::optional<Fault> parse_fault(std::string_view name);
// The classic profile's kinds (the first ten above).
const std::vector<Fault>& all_faults();
// The heavy profile's kinds: all but crc and noise, which bitflip and the three noise
// kinds replace.
const std::vector<Fault>& heavy_faults();

class FaultInjector {
 public:
  FaultInjector(double rate, std::vector<Fault> kinds, Rng rng)
      : rate_(rate), kinds_(std::move(kinds)), rng_(rng) {}

  // The fault of the next transaction, if any.
  std::optional<Fault> draw();
  // The heavy profile's faults of the next transaction: none, one, or (a quarter of the
  // faulty ones) two different kinds.
  std::vector<Fault> draw_heavy();

  // Flips one bit in a byte after the function code, so the frame keeps its address and
  // function (and a length-predicting framer can still place it) but fails its CRC.
  void corrupt(Bytes& adu);
  // Idle-time interference: 1-12 random bytes.
  Bytes noise_burst();
  // Line turnaround glitch: 1-3 bytes, all 0x00 or all 0xFF.
  Bytes turnaround_burst();
  // How many of the `size` bytes of a frame get onto the wire before it breaks off.
  std::size_t truncated_size(std::size_t size);
  // Silence strictly between t1.5 and t3.5.
  Nanos pause(const LineSettings& line);
  // Silence from half a character up to 80% of t3.5.
  Nanos short_gap(const LineSettings& line);
  // Any valid unicast address but `asked`.
  std::uint8_t other_address(std::uint8_t asked);

  // Heavy profile.
  // Flips 1-3 distinct bits in one or two bytes anywhere in the frame; returns the indices
  // of the bytes changed, ascending. CRC-16/MODBUS has the factor x+1 and catches every
  // error of up to three bits in a frame this short, so the frame always fails its CRC.
  std::vector<std::size_t> flip_bits(Bytes& adu);
  // Silence between a burst and the frame it touches: 0 to 90% of t3.5.
  Nanos touching_gap(const LineSettings& line);
  // A lone glitch byte: half of them the values a short spike reads as (a start bit and
  // then ones from where the line settles: 0xFE, 0xFC, ... 0x00, 0xFF), half any value.
  std::uint8_t glitch_byte();
  // Silence before the glitch byte: 50-150 us after the frame's last stop bit.
  Nanos glitch_delay();
  // Silence before an early response: 0.1 ms to 93% of t1.5 (0.1-0.7 ms above 19200 baud).
  Nanos fast_gap(const LineSettings& line);
  // A unicast address none of `present` uses.
  std::uint8_t absent_address(const std::vector<std::uint8_t>& present);

  Rng& rng() { return rng_; }

 private:
  double rate_;
  std::vector<Fault> kinds_;
  Rng rng_;
};

}  // namespace rtu::sim
