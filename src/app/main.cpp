// rtuscope command line: argument parsing and wiring only. The subcommands live in
// cmd_*.cpp and register themselves (command.hpp).
#include <fmt/format.h>

#include <csignal>
#include <exception>
#include <vector>

#include "app/command.hpp"
#include "core/input_error.hpp"
#include "core/output_error.hpp"

namespace rtu::app {
namespace {

std::vector<CommandSetup>& registry() {
  static std::vector<CommandSetup> commands;
  return commands;
}

}  // namespace

bool register_command(CommandSetup setup) {
  registry().push_back(std::move(setup));
  return true;
}

}  // namespace rtu::app

int main(int argc, char** argv) {
  CLI::App app{"rtuscope: passive Modbus RTU bus analyzer"};
  // A reader that goes away (`rtuscope decode x | head`, a closed pipe to a service) shows as
  // a write error the run can end on cleanly, recording finished, instead of killing it.
  std::signal(SIGPIPE, SIG_IGN);
  app.set_version_flag("--version", RTUSCOPE_VERSION);
  app.require_subcommand(1);
  int exit_code = 0;
  for (const auto& setup : rtu::app::registry()) setup(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Bad arguments are unusable input: exit 2 (CLI11's help/version exit 0).
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const rtu::OutputError& e) {
    fmt::print(stderr, "rtuscope: {}\n", e.what());
    return 1;
  } catch (const rtu::InputError& e) {
    fmt::print(stderr, "rtuscope: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rtuscope: error: {}\n", e.what());
    return 2;
  }
  return exit_code;
}
