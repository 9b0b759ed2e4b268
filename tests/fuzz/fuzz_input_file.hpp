#pragma once
// The readers under fuzz take a path, not bytes. Each run rewrites one in-memory file
// (memfd) and hands over its /proc/self/fd path: no disk I/O, no file left behind, and the
// reader opens it afresh as it would any capture.
#include <cstddef>
#include <cstdint>
#include <string>

namespace rtu::fuzz {

class FuzzInputFile {
 public:
  FuzzInputFile();
  ~FuzzInputFile();
  FuzzInputFile(const FuzzInputFile&) = delete;
  FuzzInputFile& operator=(const FuzzInputFile&) = delete;

  // Replaces the file's content with `data`; aborts when that fails (the run would test
  // nothing).
  void write(const std::uint8_t* data, std::size_t size);
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  int fd_ = -1;
  std::string path_;
};

// One file per process, created on first use.
FuzzInputFile& fuzz_input_file();

}  // namespace rtu::fuzz
