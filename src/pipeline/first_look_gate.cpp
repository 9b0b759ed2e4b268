#include "pipeline/first_look_gate.hpp"

namespace rtu {

void FirstLookGate::on_capture(const CaptureInfo& info) {
  if (look_ == nullptr) {
    pairing_.on_capture(info);
    return;
  }
  info_ = info;
  looking_ = &look_->start_look(info);
  looking_->on_capture(info);
}

void FirstLookGate::on_record(Record& record) {
  if (looking_ == nullptr) {
    pairing_.on_record(record);
    return;
  }
  held_.hold(record);  // before the look may change it (a tracker fills in its fields)
  looking_->on_record(record);
  if (look_->seen_enough()) {
    end_look(SampleEnd::kEnough);
  } else if (held_.bytes_held() >= FirstLook::kMaxHeldBytes) {
    end_look(SampleEnd::kHeldBound);
  }
}

void FirstLookGate::advance(Nanos now) {
  if (looking_ == nullptr) {
    pairing_.advance(now);
    return;
  }
  held_.hold_advance(now);
  looking_->advance(now);
}

void FirstLookGate::on_break() {
  if (looking_ == nullptr) {
    pairing_.on_break();
    return;
  }
  held_.hold_break();
  looking_->on_break();
}

void FirstLookGate::on_finish() {
  if (looking_ != nullptr) end_look(SampleEnd::kCaptureEnd);
  pairing_.on_finish();
}

void FirstLookGate::end_look(SampleEnd why) {
  looking_->on_finish();
  looking_ = nullptr;
  look_->conclude(why);
  pairing_.on_capture(info_);
  held_.tell(pairing_);
}

}  // namespace rtu
