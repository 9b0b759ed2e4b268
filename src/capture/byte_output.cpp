#include "capture/byte_output.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/input_error.hpp"

namespace rtu {

void MemoryOutput::write(std::span<const std::uint8_t> unit) {
  bytes_.insert(bytes_.end(), unit.begin(), unit.end());
}

FileOutput::FileOutput(std::string path, bool append) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | (append ? O_APPEND : O_TRUNC) | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw InputError(fmt::format("{}: cannot create: {}", path_, std::strerror(errno)));
  }
  buffer_.reserve(kBufferSize);
}

FileOutput::~FileOutput() {
  try {
    flush();
  } catch (const InputError&) {
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
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      throw InputError(fmt::format("{}: write failed: {}", path_, std::strerror(errno)));
    }
    bytes = bytes.subspan(static_cast<std::size_t>(n));
  }
}

}  // namespace rtu
