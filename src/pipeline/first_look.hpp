#pragma once
// A first look at a capture's first records, taken in the decoding pass itself before its
// sink sees any of them: identification looks at a sample of the traffic to choose how the
// whole of it is decoded, the sample included. Taking the look in the one pass frames the
// sample once; a pass of its own over the sample framed it twice, which on traffic dear to
// frame (a sick bus, random frames) cost as much as the report itself.
#include <cstddef>

#include "framing/capture_info.hpp"
#include "pairing/pairing_input.hpp"
#include "report/identification_sample.hpp"

namespace rtu {

class FirstLook {
 public:
  virtual ~FirstLook() = default;
  // Where the look takes the framing's records and decided times (a tracker of its own, say),
  // told first the capture they come from. Asked once, before the first record.
  virtual PairingInput& start_look(const CaptureInfo& info) = 0;
  // Asked after each record: true once the look has seen enough.
  [[nodiscard]] virtual bool seen_enough() const = 0;
  // The look is over, for the reason `why` (kHeldBound: the records held for the sink reached
  // kMaxHeldBytes), its input finished: called once, before the sink's first record.
  virtual void conclude(SampleEnd why) = 0;

  // What the decoding holds back for the sink while the look lasts, at most: the look ends
  // there even if it has not seen enough, so memory stays bounded whatever the traffic.
  // 200,000 short frames hold about 18 MB.
  static constexpr std::size_t kMaxHeldBytes = 24 * 1024 * 1024;
};

}  // namespace rtu
