#include "capture/byte_output.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/input_error.hpp"
#include "core/output_error.hpp"

namespace rtu {

void MemoryOutput::write(std::span<const std::uint8_t> unit) {
  bytes_.insert(bytes_.end(), unit.begin(), unit.end());
}

FileOutput::FileOutput(std::string path, bool append) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | (append ? O_APPEND : O_TRUNC) | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw InputError(fmt::format("{}: cannot create: {}", path_, std::strerror(errno)));
  }
  if (append) {
    const off_t end = ::lseek(fd_, 0, SEEK_END);
    committed_ = end > 0 ? static_cast<std::uint64_t>(end) : 0;
  }
  buffer_.reserve(kBufferSize);
}

FileOutput::~FileOutput() {
  try {
    flush();
  } catch (const OutputError&) {
    // Destructors must not throw; a caller that cares calls flush() first.
  }
  ::close(fd_);
}

void FileOutput::write(std::span<const std::uint8_t> unit) {
  if (buffer_.size() + unit.size() > kBufferSize) flush();
  if (unit.size() >= kBufferSize) {
    write_all(unit);
    return;
  }
  buffer_.insert(buffer_.end(), unit.begin(), unit.end());
}

void FileOutput::flush() {
  if (buffer_.empty()) return;
  write_all(buffer_);
  buffer_.clear();
}

void FileOutput::write_all(std::span<const std::uint8_t> bytes) {
  if (failed_) return;
  const std::size_t total = bytes.size();
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      // A full disk takes part of a write: cut the file back to its last whole unit, so it
      // stays a valid (shorter) capture that every reader can open.
      failed_ = true;
      const bool cut = ::ftruncate(fd_, static_cast<off_t>(committed_)) == 0;
      throw OutputError(fmt::format("{}: write failed: {}; the file {} the {} bytes written before",
                                    path_, std::strerror(error),
                                    cut ? "keeps" : "could not be cut back to", committed_));
    }
    bytes = bytes.subspan(static_cast<std::size_t>(n));
  }
  committed_ += total;
}

}  // namespace rtu
