#include "app/record_writer.hpp"

#include "core/format_registry.hpp"
#include "report/record_formats.hpp"

namespace rtu::app {

std::unique_ptr<RecordSink> make_record_writer(const std::string& format, OutputStream& out) {
  return find_format_or_default(record_formats(), format).factory(out);
}

}  // namespace rtu::app
