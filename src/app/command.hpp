#pragma once
// Subcommands register themselves, so each lives in its own file (cmd_<name>.cpp) and
// main.cpp never changes when one is added.
#include <CLI/CLI.hpp>
#include <functional>

namespace rtu::app {

// Adds the subcommand to `app`; its callback must set `exit_code` via the returned
// function (0 success, 1 findings/failures where meaningful, 2 unusable input).
using CommandSetup = std::function<void(CLI::App& app, int& exit_code)>;

bool register_command(CommandSetup setup);

}  // namespace rtu::app

// Use once at namespace scope in a cmd_*.cpp file.
#define RTUSCOPE_REGISTER_COMMAND(setup_fn) \
  static const bool rtuscope_command_registered_ = ::rtu::app::register_command(setup_fn)
