#pragma once
// The registry of record output formats: how `decode`, `live` and `demo` print each record
// (--format), and the writer of each.
#include <memory>

#include "core/format_registry.hpp"
#include "core/output_stream.hpp"
#include "framing/record.hpp"

namespace rtu {

// Device registers are shown where a device stage before the writer named them.
using RecordWriterFactory = std::unique_ptr<RecordSink> (*)(OutputStream& out);

// "text" (the default, first) and "jsonl".
const FormatTable<RecordWriterFactory>& record_formats();

}  // namespace rtu
