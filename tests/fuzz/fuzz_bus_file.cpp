// Fuzz target for the bus-file loader (dissect/map_loader.hpp, load_bus_text; what
// `--bus FILE` reads): the input is the TOML text of a bus file.
//
// Oracles: the loader returns or throws InputError "fuzz-bus.toml:LINE: ..." with a line of
// the input; nothing else escapes. What it accepts is what dissectors/README.md allows: baud
// 50..4000000, stop 1 or 2, timeout 1..600000 ms, slave addresses 1..247 each given once,
// models that are model keys, one or two live ports, keep ≤ 1000000, and no empty string
// where a value was given.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <string_view>

#include "core/input_error.hpp"
#include "dissect/map_loader.hpp"
#include "fuzz_oracle.hpp"

namespace {

using rtu::fuzz::fail;

constexpr std::string_view kTarget = "fuzz_bus_file";
constexpr std::string_view kFile = "fuzz-bus.toml";

bool is_model_key(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

void check_bus(const rtu::dissect::BusConfig& bus) {
  if (bus.baud && (*bus.baud < 50 || *bus.baud > 4000000)) fail(kTarget, "baud out of range", "");
  if (bus.stop_bits && *bus.stop_bits != 1 && *bus.stop_bits != 2) {
    fail(kTarget, "stop bits out of range", "");
  }
  if (bus.timeout_ms && (*bus.timeout_ms < 1 || *bus.timeout_ms > 600000)) {
    fail(kTarget, "timeout out of range", "");
  }
  for (std::size_t i = 0; i < bus.slaves.size(); ++i) {
    const auto& s = bus.slaves[i];
    if (s.slave < 1 || s.slave > 247) fail(kTarget, "slave address out of range", s.model);
    if (!is_model_key(s.model)) fail(kTarget, "model is not a model key", s.model);
    for (std::size_t k = 0; k < i; ++k) {
      if (bus.slaves[k].slave == s.slave) {
        fail(kTarget, "slave address given twice", std::to_string(s.slave));
      }
    }
  }
  const auto& live = bus.live;
  if (live.ports.size() > 2) fail(kTarget, "more than two live ports", "");
  for (const auto& port : live.ports) {
    if (port.empty()) fail(kTarget, "empty live port", "");
  }
  if (live.keep && *live.keep > 1000000) fail(kTarget, "keep out of range", "");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    check_bus(rtu::dissect::load_bus_text(text, kFile));
  } catch (const rtu::InputError& e) {
    rtu::fuzz::require_line(kTarget, e.what(), kFile, rtu::fuzz::count_lines(text));
  } catch (const std::exception& e) {
    fail(kTarget, "the loader threw something other than InputError", e.what());
  }
  return 0;
}
