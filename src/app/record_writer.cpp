#include "app/record_writer.hpp"

#include "report/jsonl_writer.hpp"
#include "report/text_writer.hpp"

namespace rtu::app {

std::unique_ptr<RecordSink> make_record_writer(const std::string& format, OutputStream& out,
                                               bool flush_each) {
  if (format == "jsonl") return std::make_unique<JsonlWriter>(out, flush_each);
  return std::make_unique<TextWriter>(out, flush_each);
}

}  // namespace rtu::app
