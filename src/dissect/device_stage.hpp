#pragma once
// The meaning stage: a record sink chained after the transaction tracker. For every frame it
// looks the slave up in the DeviceTable, decodes the frame once with the slave's map (named,
// scaled points; learned ratios), merges the device issues into the record's issues, and
// hangs the result on the record (Record::device) for the sinks after it: the frame writers
// show the points, reports and the CSV export follow the values over time. A slave without a
// map gets no decode, and, when values are collected, its raw registers as values.
#include <vector>

#include "dissect/device_table.hpp"
#include "dissect/point_value.hpp"
#include "dissect/raw_values.hpp"
#include "dissect/register_decoder.hpp"
#include "framing/record.hpp"
#include "modbus/data_access.hpp"

namespace rtu::dissect {

// What the stage found in one frame; valid only during the next sink's on_record.
struct DeviceReading {
  // The slave's map, or null: then `decoded` is empty and the frame is plain Modbus.
  const DeviceMap* map = nullptr;
  Decoded decoded;
  // Values over time the frame carries (only when the stage collects them): the map's whole
  // points with a value, rounded to their decimals, or raw registers for a slave without a
  // map. Only normal responses carry any (carries_values).
  std::vector<PointValue> values;
  // For a request frame, what it accesses (data_access(frame, nullptr)): found once by the
  // stage for the map's decoding and the sinks after it (the report files requests by it),
  // instead of once in each. Null for other records.
  const DataAccess* request_access = nullptr;
};

class DeviceStage final : public RecordSink {
 public:
  // `table` and `next` are not owned and must outlive the stage. `collect_values`: fill
  // DeviceReading::values (reports, CSV); the frame writers need none.
  DeviceStage(DeviceTable& table, RecordSink& next, bool collect_values = false);

  void on_capture(const CaptureInfo& info) override { next_.on_capture(info); }
  void on_record(Record& record) override;
  void on_finish() override { next_.on_finish(); }

 private:
  // on_record() for a frame, with reading_.request_access set.
  void decode_and_pass(Record& frame);
  void collect_values(const Record& frame);

  DeviceTable& table_;
  RecordSink& next_;
  bool collect_values_;
  RegisterDecoder decoder_;
  DeviceReading reading_;  // reused, so steady state does not allocate
  RawValues raw_;
};

}  // namespace rtu::dissect
