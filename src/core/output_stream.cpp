#include "core/output_stream.hpp"

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
  if (owned_) std::fclose(file_);
}

void OutputStream::write(const fmt::memory_buffer& buffer) {
  if (buffer.size() == 0) return;
  if (failed_) return;  // the error was reported once; the run is ending
  if (std::fwrite(buffer.data(), 1, buffer.size(), file_) != buffer.size()) fail(errno);
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
  if (std::fflush(file_) != 0) fail(errno);
}

void OutputStream::fail(int error) {
  failed_ = true;
  throw OutputError(fmt::format("{}: write failed: {}", path_, std::strerror(error)));
}

}  // namespace rtu
