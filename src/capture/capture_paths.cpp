#include "capture/capture_paths.hpp"

#include <fmt/format.h>
#include <glob.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <utility>

#include "capture/capture_formats.hpp"
#include "capture/capture_set_reader.hpp"
#include "capture/open_capture.hpp"
#include "capture/spooled_input.hpp"
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

// An input that gives its bytes once, and which one it is (to refuse reading it twice).
struct OnceOnly {
  dev_t device = 0;
  ino_t inode = 0;
  std::string argument;
};

SpoolOptions spool_options() {
  SpoolOptions options;
  options.on_waiting = [](const std::string& line) { fmt::print(stderr, "rtuscope: {}\n", line); };
  return options;
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

std::vector<CaptureFile> capture_inputs(const std::vector<std::string>& arguments) {
  std::vector<CaptureFile> out;
  std::vector<OnceOnly> read_once;
  const auto refuse_twice = [&read_once](const struct stat& info, const std::string& argument) {
    for (const auto& seen : read_once) {
      if (seen.device == info.st_dev && seen.inode == info.st_ino) {
        throw InputError(fmt::format("{}: the same input as {}, which can be read only once",
                                     argument, seen.argument));
      }
    }
    read_once.push_back({info.st_dev, info.st_ino, argument});
  };
  for (const auto& path : expand_capture_paths(arguments)) {
    struct stat info {};
    if (path == "-") {
      if (::isatty(STDIN_FILENO) == 1) {
        throw InputError(
            "-: standard input is a terminal; pipe a capture into it (zcat cap.hex.gz | "
            "rtuscope ... -) or name the file");
      }
      if (::fstat(STDIN_FILENO, &info) == 0) refuse_twice(info, path);
      out.push_back(spool_input(STDIN_FILENO, kStandardInputName, spool_options()));
      continue;
    }
    // A regular file is read by path, as often as needed; what does not exist or is a
    // folder is kept, so that opening it says what is wrong.
    if (::stat(path.c_str(), &info) != 0 || S_ISREG(info.st_mode) || S_ISDIR(info.st_mode)) {
      out.emplace_back(path);
      continue;
    }
    refuse_twice(info, path);
    out.push_back(spool_input(path, spool_options()));
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
         "as one capture. - reads standard input (zcat cap.pcapng.gz | rtuscope ... -); it, a FIFO "
         "or <(...) is read once, into a temporary copy in $TMPDIR (else /tmp), and may be one "
         "of several files";
}

}  // namespace rtu
