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

// The reader of one file (open_capture), or of several read as one capture in time order
// (CaptureSetReader).
std::unique_ptr<CaptureReader> open_captures(const std::vector<CaptureFile>& files,
                                             WarningSink warnings = print_warning_to_stderr);

// capture_file_help() and how several files are read, for a command's FILE arguments.
std::string capture_files_help();

}  // namespace rtu
