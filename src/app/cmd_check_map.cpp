// rtuscope check-map FILE|DIR...: runs the device-map loader over user maps and prints every
// problem as "file:line: what is wrong". A folder stands for its *.toml files, as --dissectors
// reads them. Exit 0 when all maps load, 2 otherwise.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/command.hpp"
#include "dissect/map_loader.hpp"

namespace rtu::app {
namespace {

// The map files a FILE argument names: itself, or a folder's *.toml files in name order
// (none: the folder is reported and `ok` cleared).
std::vector<std::string> map_files(const std::string& argument, bool& ok) {
  std::error_code ec;
  if (!std::filesystem::is_directory(argument, ec)) return {argument};
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(argument, ec)) {
    if (entry.is_regular_file(ec) && entry.path().extension() == ".toml") {
      files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    fmt::print(stderr, "{}: is a directory and holds no device maps (*.toml)\n", argument);
    ok = false;
  }
  return files;
}

void setup(CLI::App& app, int& exit_code) {
  auto files = std::make_shared<std::vector<std::string>>();
  auto* cmd = app.add_subcommand("check-map", "check device maps (dissectors/*.toml) for errors");
  cmd->add_option("FILE", *files, "device map files, or folders of them (their *.toml files)")
      ->required();
  cmd->callback([files, &exit_code] {
    int status = 0;
    std::vector<std::string> maps;
    for (const auto& argument : *files) {
      bool ok = true;
      for (auto& file : map_files(argument, ok)) maps.push_back(std::move(file));
      if (!ok) status = 2;
    }
    for (const auto& file : maps) {
      const auto result = dissect::load_map_file(file);
      for (const auto& e : result.errors) fmt::print(stderr, "{}\n", e);
      if (!result.ok()) {
        status = 2;
        continue;
      }
      std::size_t points = 0;
      for (const auto& s : result.map.spaces) points += s.points.size();
      fmt::print("{}: ok: model {}, {} spaces, {} points\n", file, result.map.model,
                 result.map.spaces.size(), points);
    }
    exit_code = status;
  });
}

}  // namespace

RTUSCOPE_REGISTER_COMMAND(setup);

}  // namespace rtu::app
