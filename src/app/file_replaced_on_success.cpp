#include "app/file_replaced_on_success.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <utility>

#include "core/output_error.hpp"

namespace rtu::app {

FileReplacedOnSuccess::FileReplacedOnSuccess(std::string path)
    : path_(std::move(path)), temporary_(path_ + ".partial") {}

FileReplacedOnSuccess::~FileReplacedOnSuccess() {
  if (!committed_) std::remove(temporary_.c_str());
}

void FileReplacedOnSuccess::commit() {
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0) {
    throw OutputError(
        fmt::format("{}: cannot rename {} to it: {}", path_, temporary_, std::strerror(errno)));
  }
  committed_ = true;
}

}  // namespace rtu::app
