#pragma once
// The frame writer of the commands that print records (`decode`, `live`, `demo`): one place
// that maps --format to a writer.
#include <memory>
#include <string>

#include "core/output_stream.hpp"
#include "framing/record.hpp"

namespace rtu::app {

// `format` is a name in record_formats() ("text", "jsonl"; others give text). Device registers
// are shown where a device stage before the writer named them.
[[nodiscard]] std::unique_ptr<RecordSink> make_record_writer(const std::string& format,
                                                             OutputStream& out);

}  // namespace rtu::app
