#include "core/output_stream.hpp"

#include <cerrno>
#include <cstring>

#include "core/input_error.hpp"

namespace rtu {

OutputStream::OutputStream(const std::string& path) : path_(path) {
  if (path.empty() || path == "-") {
    file_ = stdout;
    path_ = "standard output";
    return;
  }
  file_ = std::fopen(path.c_str(), "wb");
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
  if (std::fwrite(buffer.data(), 1, buffer.size(), file_) != buffer.size()) {
    throw InputError(fmt::format("{}: write failed: {}", path_, std::strerror(errno)));
  }
}

void OutputStream::flush() {
  std::fflush(file_);
}

}  // namespace rtu
