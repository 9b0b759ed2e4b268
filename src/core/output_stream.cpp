#include "core/output_stream.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/input_error.hpp"
#include "core/output_error.hpp"

namespace rtu {

OutputStream::OutputStream(const std::string& path, Mode mode) : path_(path) {
  if (path.empty() || path == "-") {
    file_ = stdout;
    path_ = "standard output";
    return;
  }
  file_ = std::fopen(path.c_str(), mode == Mode::kAppend ? "ab" : "wb");
  if (file_ == nullptr) {
    throw InputError(fmt::format("{}: cannot create: {}", path, std::strerror(errno)));
  }
  owned_ = true;
}

OutputStream::~OutputStream() {
  // Records still held when a run ends by an exception are written all the same.
  if (whole_records_ && !failed_ && held_.size() > 0) {
    try {
      put_held();
    } catch (const OutputError&) {
      // Nowhere left to say it: the run is already ending on another error.
    }
  }
  if (owned_) std::fclose(file_);
}

void OutputStream::write(const fmt::memory_buffer& buffer) {
  if (buffer.size() == 0) return;
  if (failed_) return;  // the error was reported once; the run is ending
  if (whole_records_) {
    if (held_.size() > 0 && held_.size() + buffer.size() > kWholeWriteBytes) put_held();
    held_.append(buffer);
    return;
  }
  if (std::fwrite(buffer.data(), 1, buffer.size(), file_) != buffer.size()) fail(errno);
}

void OutputStream::keep_records_whole() {
  flush();
  whole_records_ = true;
}

// Straight to the descriptor: stdio would split a batch at its buffer's edge (or, on a
// terminal, at every line).
void OutputStream::put_held() {
  const char* data = held_.data();
  std::size_t left = held_.size();
  held_.clear();
  while (left > 0) {
    const ssize_t n = ::write(::fileno(file_), data, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail(n < 0 ? errno : EIO);
    data += n;
    left -= static_cast<std::size_t>(n);
  }
}

void OutputStream::reopen() {
  if (!owned_) return;
  std::FILE* reopened = std::fopen(path_.c_str(), "ab");
  if (reopened == nullptr) {
    throw InputError(fmt::format("{}: cannot open again: {}", path_, std::strerror(errno)));
  }
  flush();
  std::fclose(file_);
  file_ = reopened;
}

void OutputStream::flush() {
  if (failed_) return;
  if (whole_records_) {
    if (held_.size() > 0) put_held();
    return;
  }
  if (std::fflush(file_) != 0) fail(errno);
}

void OutputStream::fail(int error) {
  failed_ = true;
  throw OutputError(fmt::format("{}: write failed: {}", path_, std::strerror(error)));
}

}  // namespace rtu
