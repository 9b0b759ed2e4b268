#include "app/file_replaced_on_success.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <utility>

#include "core/output_error.hpp"

namespace rtu::app {

FileReplacedOnSuccess::FileReplacedOnSuccess(std::string path) : path_(std::move(path)) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path_, error);
  direct_ = !error && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status);
  temporary_ = direct_ ? path_ : path_ + ".partial";
}

FileReplacedOnSuccess::~FileReplacedOnSuccess() {
  if (!committed_ && !direct_) std::remove(temporary_.c_str());
}

void FileReplacedOnSuccess::commit() {
  if (direct_) {
    committed_ = true;
    return;
  }
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0) {
    throw OutputError(
        fmt::format("{}: cannot rename {} to it: {}", path_, temporary_, std::strerror(errno)));
  }
  committed_ = true;
}

}  // namespace rtu::app
