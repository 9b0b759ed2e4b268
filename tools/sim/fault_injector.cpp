#include "fault_injector.hpp"

#include <array>

namespace rtu::sim {
namespace {

struct FaultEntry {
  Fault fault;
  std::string_view name;
};

constexpr std::array<FaultEntry, 10> kFaults{{
    {Fault::kCrc, "crc"},
    {Fault::kNoise, "noise"},
    {Fault::kTurnaround, "turnaround"},
    {Fault::kTruncated, "truncated"},
    {Fault::kTimeout, "timeout"},
    {Fault::kException, "exception"},
    {Fault::kPause, "pause"},
    {Fault::kShortGap, "short_gap"},
    {Fault::kBroadcast, "broadcast"},
    {Fault::kWrongSlave, "wrong_slave"},
}};

}  // namespace

std::string_view fault_name(Fault f) {
  for (const auto& e : kFaults) {
    if (e.fault == f) return e.name;
  }
  return "?";
}

std::optional<Fault> parse_fault(std::string_view name) {
  for (const auto& e : kFaults) {
    if (e.name == name) return e.fault;
  }
  return std::nullopt;
}

const std::vector<Fault>& all_faults() {
  static const std::vector<Fault> faults = [] {
    std::vector<Fault> v;
    for (const auto& e : kFaults) v.push_back(e.fault);
    return v;
  }();
  return faults;
}

std::optional<Fault> FaultInjector::draw() {
  // Always draw both numbers, so the sequence of transactions a seed gives does not depend
  // on the rate.
  const bool faulty = rng_.chance(rate_);
  const std::uint64_t pick = rng_.next();
  if (!faulty || kinds_.empty()) return std::nullopt;
  return kinds_[pick % kinds_.size()];
}

void FaultInjector::corrupt(Bytes& adu) {
  if (adu.size() < 3) return;
  const std::size_t at = 2 + rng_.below(adu.size() - 2);
  adu[at] = static_cast<std::uint8_t>(adu[at] ^ (1U << rng_.below(8)));
}

Bytes FaultInjector::noise_burst() {
  Bytes b(static_cast<std::size_t>(rng_.between(1, 12)));
  for (auto& x : b) x = rng_.byte();
  return b;
}

Bytes FaultInjector::turnaround_burst() {
  const std::uint8_t value = rng_.chance(0.5) ? 0x00 : 0xFF;
  return Bytes(static_cast<std::size_t>(rng_.between(1, 3)), value);
}

std::size_t FaultInjector::truncated_size(std::size_t size) {
  if (size < 2) return size;
  return 1 + static_cast<std::size_t>(rng_.below(size - 1));
}

Nanos FaultInjector::pause(const LineSettings& line) {
  const Nanos lo = line.t1_5();
  const Nanos hi = line.t3_5();
  const Nanos margin = (hi - lo) / 10;
  return rng_.nanos(lo + margin, hi - margin);
}

Nanos FaultInjector::short_gap(const LineSettings& line) {
  return rng_.nanos(line.char_time() / 2, line.t3_5() * 4 / 5);
}

std::uint8_t FaultInjector::other_address(std::uint8_t asked) {
  std::uint8_t a = asked;
  while (a == asked) a = static_cast<std::uint8_t>(rng_.between(1, 247));
  return a;
}

}  // namespace rtu::sim
