#pragma once
// A capture to read: where its bytes are, and the name that messages and outputs call it by.
// The two differ for an input read from a pipe (capture/spooled_input.hpp): the passes read
// a temporary copy, but the user must only ever see the input as they named it.
#include <memory>
#include <string>
#include <utility>

namespace rtu {

struct CaptureFile {
  // A file is named by its own path; implicit, so that every path is a capture to read.
  CaptureFile(std::string file_path)  // NOLINT(google-explicit-constructor)
      : path(file_path), name(std::move(file_path)) {}
  CaptureFile(const char* file_path)  // NOLINT(google-explicit-constructor)
      : CaptureFile(std::string(file_path)) {}
  CaptureFile(std::string file_path, std::string shown_name, std::shared_ptr<const void> copy)
      : path(std::move(file_path)), name(std::move(shown_name)), keep_alive(std::move(copy)) {}

  std::string path;  // what to open
  std::string name;  // what to call it
  // The temporary copy `path` refers to, if any: it stays readable while a CaptureFile (a
  // pass's opener holds one) refers to it.
  std::shared_ptr<const void> keep_alive;
};

}  // namespace rtu
