#include "app/line_options.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cstdint>
#include <system_error>

#include "core/input_error.hpp"

namespace rtu::app {

void LineOptions::add_to(CLI::App& command, bool with_resolution) {
  auto_baud_allowed = with_resolution;
  if (with_resolution) {
    command.add_option("--baud", baud,
                       "Baud rate, or 'auto' to infer it (and the character size) from the byte "
                       "timing (default: from the file, else inferred where bytes have their own "
                       "timestamps, else 9600)");
  } else {
    command.add_option("--baud", baud, "Baud rate (default: 9600; 'rtuscope probe' finds it)");
  }
  command.add_option("--parity", parity, "Parity N|E|O (default: from the file, else E)");
  command.add_option("--stop", stop_bits, "Stop bits 1|2 (default: from the file, else 1)")
      ->check(CLI::IsMember({1U, 2U}));
  timeout_option =
      command
          .add_option("--timeout-ms", timeout_ms,
                      "Response timeout in ms (default: what a live recording declares, else 1000)")
          ->check(CLI::PositiveNumber);
  if (!with_resolution) return;
  command
      .add_option("--resolution-ms", resolution_ms,
                  "Timing resolution of the capture in ms (default: estimated from the data)")
      ->check(CLI::NonNegativeNumber);
}

ReplayOptions LineOptions::to_replay_options() const {
  ReplayOptions options;
  if (baud == "auto" && auto_baud_allowed) {
    options.overrides.infer_baud = true;
  } else if (baud == "auto") {
    throw InputError(
        "--baud auto infers the rate from a capture's timing; a port's settings are found by "
        "listening: rtuscope probe PORT");
  } else if (!baud.empty()) {
    std::uint32_t rate = 0;
    const auto* end = baud.data() + baud.size();
    const auto [ptr, ec] = std::from_chars(baud.data(), end, rate);
    if (ec != std::errc{} || ptr != end || rate < 50 || rate > 20000000) {
      throw InputError(fmt::format("--baud: expected a rate from 50 to 20000000{}, found '{}'",
                                   auto_baud_allowed ? " or 'auto'" : "", baud));
    }
    options.overrides.baud = rate;
  }
  if (!parity.empty()) {
    options.overrides.parity = parse_parity(parity);
    if (!options.overrides.parity) {
      throw InputError(fmt::format("--parity: expected N, E or O, found '{}'", parity));
    }
  }
  if (stop_bits) options.overrides.stop_bits = static_cast<std::uint8_t>(*stop_bits);
  options.response_timeout = static_cast<Nanos>(timeout_ms * 1e6);
  options.response_timeout_set = timeout_option != nullptr && timeout_option->count() > 0;
  if (resolution_ms) options.resolution = static_cast<Nanos>(*resolution_ms * 1e6);
  return options;
}

}  // namespace rtu::app
