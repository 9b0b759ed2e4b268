#pragma once
// What the framing half of the decoding tells the pairing half, in order: records in time
// order, and how far the line is decided (no record still to come can start before then).
// The transaction tracker takes it directly; a replay may instead hand it to another
// thread that feeds a tracker there in the same order (pipeline/framing_ahead.hpp).
#include "core/time.hpp"
#include "framing/record.hpp"

namespace rtu {

class PairingInput : public RecordSink {
 public:
  // No record can start before `now`.
  virtual void advance(Nanos now) = 0;
  // The capture stopped and started again: a recording's end followed by another file of
  // the set (a recorder started again). What was pending is decided as at the end of a
  // capture, and nothing before pairs with anything after.
  virtual void on_break() = 0;
};

}  // namespace rtu
