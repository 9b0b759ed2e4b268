#pragma once
// The frame writer of the commands that print records (`decode`, `live`, `demo`): one place
// that maps --format to a writer.
#include <memory>
#include <string>

#include "core/output_stream.hpp"
#include "framing/record.hpp"
#include "report/frame_annotator.hpp"

namespace rtu::app {

// `format` is a name in record_formats() ("text", "jsonl"; others give text). `annotator` (may be
// null) names device registers. `flush_each`: every record reaches `out` at once (live output),
// else buffered.
[[nodiscard]] std::unique_ptr<RecordSink> make_record_writer(const std::string& format,
                                                             OutputStream& out,
                                                             FrameAnnotator* annotator,
                                                             bool flush_each);

}  // namespace rtu::app
