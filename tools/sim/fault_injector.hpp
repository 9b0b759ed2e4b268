#pragma once
// Which transactions go wrong, and how. A transaction gets at most one fault, with the
// configured probability, of a kind drawn uniformly from the enabled kinds. The injector
// owns its own random stream, so the fault rate does not change the values the devices
// report, only what happens to their frames.
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
};

// Command-line names ("crc", "noise", …), in the order above.
std::string_view fault_name(Fault f);
std::optional<Fault> parse_fault(std::string_view name);
const std::vector<Fault>& all_faults();

class FaultInjector {
 public:
  FaultInjector(double rate, std::vector<Fault> kinds, Rng rng)
      : rate_(rate), kinds_(std::move(kinds)), rng_(rng) {}

  // The fault of the next transaction, if any.
  std::optional<Fault> draw();

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

  Rng& rng() { return rng_; }

 private:
  double rate_;
  std::vector<Fault> kinds_;
  Rng rng_;
};

}  // namespace rtu::sim
