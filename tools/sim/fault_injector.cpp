#include "fault_injector.hpp"

#include <algorithm>
#include <array>
#include <utility>

namespace rtu::sim {
namespace {

struct FaultEntry {
  Fault fault;
  std::string_view name;
};

constexpr std::size_t kClassicKinds = 10;

constexpr std::array<FaultEntry, 17> kFaults{{
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
    {Fault::kBitflip, "bitflip"},
    {Fault::kNoiseBefore, "noise_before"},
    {Fault::kNoiseAfter, "noise_after"},
    {Fault::kNoiseGap, "noise_gap"},
    {Fault::kGlitch, "glitch"},
    {Fault::kFastResponse, "fast_response"},
    {Fault::kDeadSlave, "dead_slave"},
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
    for (std::size_t i = 0; i < kClassicKinds; ++i) v.push_back(kFaults[i].fault);
    return v;
  }();
  return faults;
}

const std::vector<Fault>& heavy_faults() {
  static const std::vector<Fault> faults = [] {
    std::vector<Fault> v;
    for (const auto& e : kFaults) {
      if (e.fault != Fault::kCrc && e.fault != Fault::kNoise) v.push_back(e.fault);
    }
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

std::vector<Fault> FaultInjector::draw_heavy() {
  // A fixed number of draws per transaction, whatever the outcome (see draw()).
  const bool faulty = rng_.chance(rate_);
  const std::uint64_t pick = rng_.next();
  const bool second = rng_.chance(0.25);
  const std::uint64_t pick2 = rng_.next();
  std::vector<Fault> out;
  if (!faulty || kinds_.empty()) return out;
  out.push_back(kinds_[pick % kinds_.size()]);
  const Fault other = kinds_[pick2 % kinds_.size()];
  if (second && other != out.front()) out.push_back(other);
  return out;
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

std::vector<std::size_t> FaultInjector::flip_bits(Bytes& adu) {
  std::vector<std::size_t> changed;
  if (adu.empty()) return changed;
  const std::size_t first = rng_.below(adu.size());
  // A second byte is usually close by: a disturbance lasts a few bit times.
  std::size_t second = first;
  if (adu.size() > 1 && rng_.chance(0.3)) {
    second = first + 1 < adu.size() ? first + 1 : first - 1;
  }
  const auto bits = static_cast<unsigned>(rng_.between(1, 3));
  // Distinct (byte, bit) pairs: flipping one bit twice would undo the damage.
  std::vector<std::pair<std::size_t, unsigned>> done;
  while (done.size() < bits) {
    const std::size_t at = rng_.chance(0.5) ? first : second;
    const auto bit = static_cast<unsigned>(rng_.below(8));
    bool repeat = false;
    for (const auto& d : done) repeat = repeat || (d.first == at && d.second == bit);
    if (repeat) continue;
    done.emplace_back(at, bit);
    adu[at] = static_cast<std::uint8_t>(adu[at] ^ (1U << bit));
  }
  for (const auto& d : done) changed.push_back(d.first);
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  return changed;
}

Nanos FaultInjector::touching_gap(const LineSettings& line) {
  return rng_.nanos(0, line.t3_5() * 9 / 10);
}

std::uint8_t FaultInjector::glitch_byte() {
  static constexpr std::array<std::uint8_t, 9> kSpikes{0xFE, 0xFC, 0xF8, 0xF0, 0xE0,
                                                       0xC0, 0x80, 0x00, 0xFF};
  const std::uint64_t pick = rng_.next();
  const std::uint8_t any = rng_.byte();
  return rng_.chance(0.5) ? kSpikes[pick % kSpikes.size()] : any;
}

Nanos FaultInjector::glitch_delay() {
  return rng_.nanos(50 * kNanosPerMicro, 150 * kNanosPerMicro);
}

Nanos FaultInjector::fast_gap(const LineSettings& line) {
  const Nanos lo = 100 * kNanosPerMicro;
  const Nanos hi = std::max(lo, line.t1_5() * 93 / 100);
  return rng_.nanos(lo, hi);
}

std::uint8_t FaultInjector::absent_address(const std::vector<std::uint8_t>& present) {
  for (;;) {
    const auto a = static_cast<std::uint8_t>(rng_.between(1, 247));
    if (std::find(present.begin(), present.end(), a) == present.end()) return a;
  }
}

}  // namespace rtu::sim
