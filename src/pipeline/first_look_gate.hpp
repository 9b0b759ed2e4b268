#pragma once
// Stands between the framing and the decoding's own pairing while a FirstLook lasts: what
// the framing tells goes to the look and is held (HeldRecords); once the look concludes,
// everything held is told to the pairing exactly as it came, and from then on everything
// goes straight through. So the pairing, and the sink after it, get what they would have
// got without the look, only later.
#include "pipeline/first_look.hpp"
#include "pipeline/held_records.hpp"

namespace rtu {

class FirstLookGate final : public PairingInput {
 public:
  // `look` may be null: then the gate lets everything through at once.
  FirstLookGate(FirstLook* look, PairingInput& pairing) : look_(look), pairing_(pairing) {}

  void on_capture(const CaptureInfo& info) override;
  void on_record(Record& record) override;
  void advance(Nanos now) override;
  void on_finish() override;
  void on_break() override;

 private:
  // The look is over: it concludes, and the pairing gets what was held.
  void end_look(SampleEnd why);

  FirstLook* look_;
  PairingInput& pairing_;
  PairingInput* looking_ = nullptr;  // the look's input while it lasts
  CaptureInfo info_;                 // told to the pairing once the look is over
  HeldRecords held_;
};

}  // namespace rtu
