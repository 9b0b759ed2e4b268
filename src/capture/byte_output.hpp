#pragma once
// Where capture writers put their bytes. Writers hand over one whole block (or record) per
// write(), and FileOutput only ever passes whole writes to the operating system, so a file
// that is being written holds complete blocks up to the last flush() even if the process
// dies: a reader sees a valid, merely shorter, capture.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace rtu {

class ByteOutput {
 public:
  virtual ~ByteOutput() = default;
  // One complete unit (block or record); never split.
  virtual void write(std::span<const std::uint8_t> unit) = 0;
  // Hands everything written so far to the operating system.
  virtual void flush() = 0;
};

// Collects the bytes in memory (tests, small exports).
class MemoryOutput final : public ByteOutput {
 public:
  void write(std::span<const std::uint8_t> unit) override;
  void flush() override {}
  [[nodiscard]] const std::vector<std::uint8_t>& bytes() const { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
};

// Creates (or truncates) a file. Buffers up to kBufferSize bytes of whole units and writes
// them with one system call each time the buffer would overflow, on flush(), and on
// destruction. Throws InputError naming the path if it cannot be created, and OutputError if
// a write fails (a full disk): the file is then cut back to the end of its last whole unit,
// and later writes do nothing.
class FileOutput final : public ByteOutput {
 public:
  // Creates (or truncates) the file; with `append`, keeps what it holds and writes after it.
  explicit FileOutput(std::string path, bool append = false);
  ~FileOutput() override;
  FileOutput(const FileOutput&) = delete;
  FileOutput& operator=(const FileOutput&) = delete;

  void write(std::span<const std::uint8_t> unit) override;
  void flush() override;
  [[nodiscard]] const std::string& path() const { return path_; }

  static constexpr std::size_t kBufferSize = 64 * 1024;

 private:
  void write_all(std::span<const std::uint8_t> bytes);
  std::string path_;
  int fd_ = -1;
  std::vector<std::uint8_t> buffer_;
  std::uint64_t committed_ = 0;  // bytes in the file, all whole units
  bool failed_ = false;
};

}  // namespace rtu
