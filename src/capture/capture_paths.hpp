#pragma once
// The capture files a command's FILE arguments name, and one reader for all of them.
#include <memory>
#include <string>
#include <vector>

#include "capture/capture_file.hpp"
#include "capture/capture_reader.hpp"
#include "capture/capture_warnings.hpp"

namespace rtu {

// Each argument that names an existing file is that file. One holding '*', '?' or '[' is a
// glob pattern that rtuscope expands itself (quoted, it reaches rtuscope as typed, on any
// shell), into its matches in name order. Anything else is kept, so that opening it says what
// is wrong. A path named twice is kept once. Throws InputError for a pattern nothing matches.
std::vector<std::string> expand_capture_paths(const std::vector<std::string>& arguments);

// The captures the FILE arguments name (expand_capture_paths), each ready for every pass of
// a replay to read. `-` is standard input; it, and any input that is not a regular file (a
// pipe, a FIFO, /dev/stdin, a process substitution such as /dev/fd/63), is read here once
// into a temporary copy (capture/spooled_input.hpp) that messages never name. Throws
// InputError when `-` is a terminal, when one such input is named twice (`-` and /dev/stdin),
// or when such an input is empty or cannot be read or copied.
std::vector<CaptureFile> capture_inputs(const std::vector<std::string>& arguments);

// What `-` is called in messages and output headers.
inline constexpr const char* kStandardInputName = "standard input";

// The reader of one file (open_capture), or of several read as one capture in time order
// (CaptureSetReader).
std::unique_ptr<CaptureReader> open_captures(const std::vector<CaptureFile>& files,
                                             WarningSink warnings = print_warning_to_stderr);

// capture_file_help() and how several files are read, for a command's FILE arguments.
std::string capture_files_help();

}  // namespace rtu
