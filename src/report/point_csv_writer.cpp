#include "report/point_csv_writer.hpp"

#include "core/time_format.hpp"
#include "dissect/device_stage.hpp"

namespace rtu {

namespace {

void append_field(fmt::memory_buffer& b, std::string_view text) {
  if (text.find_first_of(",\"\n\r") == std::string_view::npos) {
    b.append(text);
    return;
  }
  b.push_back('"');
  for (const char c : text) {
    if (c == '"') b.push_back('"');
    b.push_back(c);
  }
  b.push_back('"');
}

}  // namespace

PointCsvWriter::PointCsvWriter(OutputStream& out) : out_(out) {
  buffer_.append(std::string_view("time,slave,point,value,unit\n"));
}

PointCsvWriter::~PointCsvWriter() {
  try {
    flush();
  } catch (...) {  // NOLINT(bugprone-empty-catch): a destructor must not throw
  }
}

void PointCsvWriter::on_record(Record& record) {
  if (record.device == nullptr) return;
  for (const dissect::PointValue& v : record.device->values) add(v);
}

void PointCsvWriter::add(const dissect::PointValue& s) {
  append_seconds(buffer_, s.t, 6);
  fmt::format_to(std::back_inserter(buffer_), ",{},", s.slave);
  append_field(buffer_, s.point);
  fmt::format_to(std::back_inserter(buffer_), ",{},", s.value);
  append_field(buffer_, s.unit);
  buffer_.push_back('\n');
  if (buffer_.size() > 64 * 1024) flush();
}

void PointCsvWriter::flush() {
  out_.write(buffer_);
  buffer_.clear();
}

}  // namespace rtu
