#include "capture/pipe_output.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/input_error.hpp"
#include "core/output_error.hpp"

namespace rtu {

PipeOutput::PipeOutput(std::string path) : path_(std::move(path)) {
  do {
    fd_ = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
  } while (fd_ < 0 && errno == EINTR);
  if (fd_ < 0) {
    throw InputError(fmt::format("{}: cannot open for writing: {}", path_, std::strerror(errno)));
  }
}

PipeOutput::~PipeOutput() {
  ::close(fd_);
}

void PipeOutput::write(std::span<const std::uint8_t> unit) {
  if (gone_) {
    ++dropped_;
    return;
  }
  while (!unit.empty()) {
    const ssize_t n = ::write(fd_, unit.data(), unit.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EPIPE) {
        gone_ = true;
        ++dropped_;
        return;
      }
      throw OutputError(fmt::format("{}: write failed: {}", path_, std::strerror(errno)));
    }
    unit = unit.subspan(static_cast<std::size_t>(n));
  }
}

bool PipeOutput::reader_gone() {
  if (gone_) return true;
  // The write end of a pipe whose reader has closed polls as POLLERR.
  pollfd p{fd_, 0, 0};
  if (::poll(&p, 1, 0) > 0 && (p.revents & (POLLERR | POLLHUP)) != 0) gone_ = true;
  return gone_;
}

}  // namespace rtu
