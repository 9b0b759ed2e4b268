#include "fuzz_input_file.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace rtu::fuzz {

FuzzInputFile::FuzzInputFile() : fd_(memfd_create("rtuscope-fuzz-input", MFD_CLOEXEC)) {
  if (fd_ < 0) {
    std::perror("memfd_create");
    std::abort();
  }
  path_ = "/proc/self/fd/" + std::to_string(fd_);
}

FuzzInputFile::~FuzzInputFile() {
  if (fd_ >= 0) close(fd_);
}

void FuzzInputFile::write(const std::uint8_t* data, std::size_t size) {
  if (ftruncate(fd_, 0) != 0) {
    std::perror("ftruncate");
    std::abort();
  }
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = pwrite(fd_, data + done, size - done, static_cast<off_t>(done));
    if (n <= 0) {
      std::perror("pwrite");
      std::abort();
    }
    done += static_cast<std::size_t>(n);
  }
}

FuzzInputFile& fuzz_input_file() {
  static FuzzInputFile file;
  return file;
}

}  // namespace rtu::fuzz
