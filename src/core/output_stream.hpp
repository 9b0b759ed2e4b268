#pragma once
// Where writers put their bytes: stdout or a file. A write or flush that fails (a full
// disk, a closed pipe) throws OutputError once; later calls do nothing, so a run that is
// ending because of it can still finish its other outputs.
//
// Buffered by default (a file written at the speed of decoding). Live output instead keeps
// records whole (keep_records_whole): a reader following it never sees half a line.
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

  // One call per record: `buffer` is one or more whole lines.
  void write(const fmt::memory_buffer& buffer);
  void flush();
  // From now on what is written reaches the file at flush() (or once it would outgrow one
  // atomic pipe write), in writes that each end at a record's end: one write per flush, not
  // one per record, where a live run flushes after handling each read.
  void keep_records_whole();
  [[nodiscard]] bool failed() const { return failed_; }
  // Log rotation: writes go on in a file opened again at the same path, appended to (the
  // old one may have been moved away). Nothing for standard output. Throws InputError when
  // the path cannot be opened; writes then go on in the file already open.
  void reopen();

 private:
  [[noreturn]] void fail(int error);
  void put_held();

  // A pipe write of at most this many bytes is never split (POSIX PIPE_BUF on Linux).
  static constexpr std::size_t kWholeWriteBytes = 4096;

  std::FILE* file_ = nullptr;
  bool owned_ = false;
  std::string path_;
  bool failed_ = false;
  bool whole_records_ = false;
  fmt::memory_buffer held_;  // whole records not yet written (keep_records_whole)
};

}  // namespace rtu
