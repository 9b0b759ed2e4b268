#pragma once
// Options shared by every command that decodes a capture: line settings, response timeout,
// timing resolution.
#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "pipeline/replay.hpp"

namespace rtu::app {

struct LineOptions {
  std::string baud;  // a rate, or "auto" where the command replays a capture
  std::string parity;
  std::optional<unsigned> stop_bits;
  double timeout_ms = 1000.0;
  std::optional<double> resolution_ms;
  const CLI::Option* timeout_option = nullptr;  // tells whether --timeout-ms was given
  bool auto_baud_allowed = false;               // a capture, not a port: its timing can tell

  // `with_resolution`: offer --resolution-ms (not for live ports, whose resolution is
  // measured).
  void add_to(CLI::App& command, bool with_resolution = true);
  // Throws InputError for values CLI11 cannot check by itself.
  [[nodiscard]] ReplayOptions to_replay_options() const;
};

}  // namespace rtu::app
