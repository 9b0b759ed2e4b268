#pragma once
// The master of the simulated bus: it polls every device once per poll cycle, waits for
// each answer (or its response timeout), and lets the fault injector spoil some
// transactions. Its output is the Timeline: exact bytes, exact times, exact truth.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "device_profile.hpp"
#include "fault_injector.hpp"
#include "timeline.hpp"

namespace rtu::sim {

struct BusOptions {
  LineSettings line;
  std::uint64_t seed = 1;
  // Stop after this many transactions, or when the next one would start after `duration`
  // (whichever comes first; at least one of them is set).
  std::optional<std::uint64_t> transactions;
  std::optional<Nanos> duration;
  Nanos start = 0;  // time of the first poll cycle
  Nanos cycle_period = 500 * kNanosPerMilli;
  Nanos master_timeout = 200 * kNanosPerMilli;  // the master's wait for an answer
  double fault_rate = 0;
  std::vector<Fault> fault_kinds;
  // kHeavy: one or two faults per faulty transaction, drawn from the heavy kinds (see
  // fault_injector.hpp). kClassic keeps the captures the classic options always gave.
  FaultProfile profile = FaultProfile::kClassic;
};

// Runs the whole capture. `devices` are polled in order, each at its own address.
Timeline simulate_bus(const BusOptions& options,
                      const std::vector<std::unique_ptr<DeviceProfile>>& devices);

}  // namespace rtu::sim
