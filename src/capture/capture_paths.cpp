#include "capture/capture_paths.hpp"

#include <fmt/format.h>
#include <glob.h>

#include <algorithm>
#include <filesystem>
#include <utility>

#include "capture/capture_formats.hpp"
#include "capture/capture_set_reader.hpp"
#include "capture/open_capture.hpp"
#include "core/input_error.hpp"

namespace rtu {
namespace {

std::vector<std::string> glob_matches(const std::string& pattern) {
  glob_t found{};
  const int status = ::glob(pattern.c_str(), 0, nullptr, &found);
  std::vector<std::string> out;
  if (status == 0) {
    for (std::size_t i = 0; i < found.gl_pathc; ++i) out.emplace_back(found.gl_pathv[i]);
  }
  ::globfree(&found);
  if (status == GLOB_NOMATCH || (status == 0 && out.empty())) {
    throw InputError(fmt::format("{}: no file matches this pattern", pattern));
  }
  if (status != 0) throw InputError(fmt::format("{}: cannot list the matching files", pattern));
  return out;  // glob(3) sorts them
}

}  // namespace

std::vector<std::string> expand_capture_paths(const std::vector<std::string>& arguments) {
  std::vector<std::string> out;
  const auto add = [&out](std::string path) {
    if (std::find(out.begin(), out.end(), path) == out.end()) out.push_back(std::move(path));
  };
  for (const auto& argument : arguments) {
    std::error_code ignored;
    const bool pattern = argument.find_first_of("*?[") != std::string::npos;
    if (pattern && !std::filesystem::exists(argument, ignored)) {
      for (auto& path : glob_matches(argument)) add(std::move(path));
    } else {
      add(argument);
    }
  }
  return out;
}

std::unique_ptr<CaptureReader> open_captures(const std::vector<CaptureFile>& files,
                                             WarningSink warnings) {
  if (files.size() == 1) return open_capture(files.front(), std::move(warnings));
  return std::make_unique<CaptureSetReader>(files, std::move(warnings));
}

std::string capture_files_help() {
  return capture_file_help() +
         ". Several files, or a quoted pattern such as 'site-*.pcapng', are read in time order "
         "as one capture";
}

}  // namespace rtu
