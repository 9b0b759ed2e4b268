#include "report/record_formats.hpp"

#include "report/jsonl_writer.hpp"
#include "report/text_writer.hpp"

namespace rtu {
namespace {

template <typename Writer>
std::unique_ptr<RecordSink> make_writer(OutputStream& out) {
  return std::make_unique<Writer>(out);
}

}  // namespace

const FormatTable<RecordWriterFactory>& record_formats() {
  static const FormatTable<RecordWriterFactory> kFormats = {
      {"text", "", {}, make_writer<TextWriter>},
      {"jsonl", "", {".jsonl"}, make_writer<JsonlWriter>},
  };
  return kFormats;
}

}  // namespace rtu
