#pragma once
// CSV export of register values over time, one row per value the device stage found on a
// record (DeviceReading::values), for spreadsheets:
//   time,slave,point,value,unit
// time in seconds on the input's clock (exact decimal), the point's name quoted when it
// holds a comma or a quote (RFC 4180). Rows are buffered and written in large blocks.
#include <fmt/format.h>

#include "core/output_stream.hpp"
#include "dissect/point_value.hpp"
#include "framing/record.hpp"

namespace rtu {

class PointCsvWriter : public RecordSink {
 public:
  explicit PointCsvWriter(OutputStream& out);
  ~PointCsvWriter() override;
  PointCsvWriter(const PointCsvWriter&) = delete;
  PointCsvWriter& operator=(const PointCsvWriter&) = delete;

  void on_record(Record& record) override;
  void on_finish() override { flush(); }
  void flush();  // writes what is buffered

 private:
  void add(const dissect::PointValue& value);

  OutputStream& out_;
  fmt::memory_buffer buffer_;
};

}  // namespace rtu
