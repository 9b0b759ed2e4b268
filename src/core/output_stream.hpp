#pragma once
// Where writers put their bytes: stdout or a file, written a whole record at a time so a
// reader following the output never sees half a line. A write or flush that fails (a full
// disk, a closed pipe) throws OutputError once; later calls do nothing, so a run that is
// ending because of it can still finish its other outputs.
#include <fmt/format.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace rtu {

class OutputStream {
 public:
  enum class Mode : std::uint8_t { kTruncate, kAppend };
  // "-" or empty = standard output. Throws InputError when the file cannot be created.
  explicit OutputStream(const std::string& path, Mode mode = Mode::kTruncate);
  ~OutputStream();
  OutputStream(const OutputStream&) = delete;
  OutputStream& operator=(const OutputStream&) = delete;

  void write(const fmt::memory_buffer& buffer);
  void flush();
  [[nodiscard]] bool failed() const { return failed_; }
  // Log rotation: writes go on in a file opened again at the same path, appended to (the
  // old one may have been moved away). Nothing for standard output. Throws InputError when
  // the path cannot be opened; writes then go on in the file already open.
  void reopen();

 private:
  [[noreturn]] void fail(int error);

  std::FILE* file_ = nullptr;
  bool owned_ = false;
  std::string path_;
  bool failed_ = false;
};

}  // namespace rtu
