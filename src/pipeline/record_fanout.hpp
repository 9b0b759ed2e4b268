#pragma once
// Hands every record to several sinks in turn (e.g. the screen writer and the report's
// statistics during a live run). The sinks are not owned and must outlive the fan-out.
#include <vector>

#include "framing/record.hpp"

namespace rtu {

class RecordFanout final : public RecordSink {
 public:
  void add(RecordSink& sink) { sinks_.push_back(&sink); }

  void on_capture(const CaptureInfo& info) override {
    for (RecordSink* sink : sinks_) sink->on_capture(info);
  }
  void on_record(Record& record) override {
    for (RecordSink* sink : sinks_) sink->on_record(record);
  }
  void on_finish() override {
    for (RecordSink* sink : sinks_) sink->on_finish();
  }

 private:
  std::vector<RecordSink*> sinks_;
};

}  // namespace rtu
