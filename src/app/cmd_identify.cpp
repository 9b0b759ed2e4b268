// rtuscope identify FILE: for every slave on the bus, ranks the device maps by how well they
// explain its traffic (function codes, addresses, value ranges), with the evidence.
#include <fmt/format.h>

#include <memory>
#include <string>
#include <vector>

#include "app/command.hpp"
#include "app/device_options.hpp"
#include "app/line_options.hpp"
#include "capture/capture_paths.hpp"
#include "dissect/map_identifier.hpp"
#include "pipeline/replay.hpp"

namespace rtu::app {
namespace {

struct IdentifyArgs {
  std::string file;
  LineOptions line;
  std::vector<std::string> dissector_dirs;
  unsigned top = 4;
};

void print_ranking(const std::vector<dissect::SlaveRanking>& ranking, unsigned top) {
  if (ranking.empty()) fmt::print("no slave was addressed by a valid request\n");
  for (const auto& slave : ranking) {
    fmt::print("slave {}: {} requests\n", slave.slave, slave.requests);
    unsigned shown = 0;
    for (const auto& e : slave.maps) {
      if (shown++ >= top) break;
      fmt::print(
          "  {:<10} {:5.1f}  functions {}/{} listed{}; addresses {}/{} defined{}; "
          "values {}/{} in range{}\n",
          e.map->model, e.score, e.listed_function, e.requests,
          e.rejected_function > 0 ? fmt::format(" (+{} rejected)", e.rejected_function)
                                  : std::string(),
          e.defined_units, e.units,
          e.rejected_units > 0 ? fmt::format(" (+{} rejected)", e.rejected_units) : std::string(),
          e.values_in, e.values_in + e.values_out,
          e.scale_hits > 0 ? fmt::format("; {} ratio reads", e.scale_hits) : std::string());
    }
  }
}

void setup_identify(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<IdentifyArgs>();
  auto* cmd = app.add_subcommand(
      "identify", "Rank, per slave, the device maps that best explain a capture's traffic");
  cmd->add_option("file", args->file, "Capture file (- reads standard input)")->required();
  cmd->add_option("--dissectors", args->dissector_dirs,
                  "Folder of user device maps (*.toml), added to the bundled ones")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--top", args->top, "Maps shown per slave (default 4)");
  args->line.add_to(*cmd);
  cmd->callback([args, &exit_code] {
    const ReplayOptions options = args->line.to_replay_options();
    const auto maps = DeviceOptions::load_maps(args->dissector_dirs);
    dissect::MapIdentifier identifier(maps->library);
    replay_capture(capture_inputs({args->file}), options, identifier);
    print_ranking(identifier.ranking(), args->top);
    exit_code = 0;
  });
}

RTUSCOPE_REGISTER_COMMAND(setup_identify);

}  // namespace
}  // namespace rtu::app
