// rtuscope check-map FILE...: runs the device-map loader over user maps and prints every
// problem as "file:line: what is wrong". Exit 0 when all maps load, 2 otherwise.
#include <fmt/format.h>

#include <memory>
#include <string>
#include <vector>

#include "app/command.hpp"
#include "dissect/map_loader.hpp"

namespace rtu::app {
namespace {

void setup(CLI::App& app, int& exit_code) {
  auto files = std::make_shared<std::vector<std::string>>();
  auto* cmd = app.add_subcommand("check-map", "check device maps (dissectors/*.toml) for errors");
  cmd->add_option("FILE", *files, "device map files")->required();
  cmd->callback([files, &exit_code] {
    int status = 0;
    for (const auto& file : *files) {
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
