#include "bus_simulator.hpp"

#include <algorithm>
#include <deque>

namespace rtu::sim {
namespace {

constexpr std::uint64_t kFaultStream = 0xFA17;

struct Pending {
  DeviceProfile* device;
  Exchange exchange;
};

class BusSimulator {
 public:
  BusSimulator(const BusOptions& options,
               const std::vector<std::unique_ptr<DeviceProfile>>& devices)
      : opt_(options),
        devices_(devices),
        timeline_(options.line),
        traffic_(options.seed),
        faults_(options.fault_rate, options.fault_kinds, Rng(options.seed).fork(kFaultStream)) {}

  Timeline run() {
    Nanos cycle_start = opt_.start;
    next_send_ = opt_.start;
    std::vector<Exchange> batch;
    while (!done()) {
      if (pending_.empty()) {
        if (txn_ > 0) {
          cycle_start += opt_.cycle_period;
          next_send_ = std::max(next_send_, cycle_start);
        }
        for (const auto& device : devices_) {
          batch.clear();
          device->poll_cycle(traffic_, batch);
          for (auto& ex : batch) pending_.push_back({device.get(), std::move(ex)});
        }
        if (pending_.empty()) break;
        continue;  // the new cycle may start after the duration
      }
      Pending p = std::move(pending_.front());
      pending_.pop_front();
      transaction(*p.device, std::move(p.exchange));
    }
    return std::move(timeline_);
  }

 private:
  [[nodiscard]] bool done() const {
    if (opt_.transactions && txn_ >= *opt_.transactions) return true;
    if (opt_.duration && next_send_ >= opt_.start + *opt_.duration) return true;
    return false;
  }

  [[nodiscard]] const LineSettings& line() const { return opt_.line; }
  Nanos think() { return line().t3_5() + traffic_.nanos(1 * kNanosPerMilli, 10 * kNanosPerMilli); }

  void transaction(DeviceProfile& device, Exchange ex) {
    const std::optional<Fault> fault = faults_.draw();
    const auto is = [&](Fault f) { return fault && *fault == f; };
    const std::uint64_t txn = ++txn_;
    Rng& frng = faults_.rng();

    if (is(Fault::kException)) ex = device.provoke_exception(frng);
    const bool broadcast = is(Fault::kBroadcast);
    if (broadcast) {
      ex.request = device.broadcast_write(frng);
      ex.response.reset();
    }
    if (is(Fault::kNoise)) {
      TruthRecord noise = noise_record(faults_.noise_burst(), "burst");
      const Nanos at = std::max(next_send_, timeline_.wire_end() + line().t3_5());
      const Nanos end = timeline_.emit(std::move(noise), at);
      next_send_ = end + think();
    }

    // Which side a two-sided fault hits: the request, or the response when there is one.
    const bool on_request = !ex.response || frng.chance(0.5);

    TruthRecord request = frame_record(ex.request, TruthRole::kRequest, txn, device.name());
    if (broadcast) request.faults.push_back("broadcast");
    // A plain vector and a flag rather than an optional: GCC 12 at -O3 misreads copies of
    // std::optional<std::vector> as uninitialised (-Wmaybe-uninitialized).
    bool answered = ex.response.has_value();
    Bytes response = answered ? std::move(*ex.response) : Bytes{};
    bool response_is_exception = is(Fault::kException);
    if (is(Fault::kCrc) && on_request) {
      faults_.corrupt(request.bytes);
      request.faults.push_back("crc");
      answered = false;
      if (auto reply = device.answer_to_bad_crc(request.bytes)) {
        answered = true;
        response = std::move(*reply);
      }
      response_is_exception = answered;
    }
    if (is(Fault::kTimeout)) answered = false;
    if (!answered && !broadcast) request.faults.push_back("timeout");

    Nanos start = next_send_;
    if (is(Fault::kShortGap) && on_request && !timeline_.records().empty()) {
      start = timeline_.wire_end() + faults_.short_gap(line());
    }
    std::int64_t pause_after = -1;  // index of the byte followed by a pause, or -1
    Nanos pause = 0;
    if (is(Fault::kPause) && on_request) {
      pause_after = frng.between(0, static_cast<std::int64_t>(request.bytes.size()) - 2);
      pause = faults_.pause(line());
    }
    const Nanos req_end = timeline_.emit(std::move(request), start, [&](std::size_t k) {
      return static_cast<std::int64_t>(k) == pause_after ? pause : Nanos{0};
    });

    if (!answered) {
      if (broadcast) {
        // The master leaves the slaves time to act on a broadcast (turnaround delay).
        next_send_ = req_end + 50 * kNanosPerMilli + think();
      } else {
        next_send_ = req_end + opt_.master_timeout;
      }
      return;
    }

    Nanos resp_start = req_end + line().t3_5() + device.turnaround(traffic_);
    if (is(Fault::kShortGap) && !on_request) resp_start = req_end + faults_.short_gap(line());
    if (is(Fault::kTurnaround)) resp_start = turnaround_burst(req_end, resp_start);

    TruthRecord resp = frame_record(std::move(response), TruthRole::kResponse, txn, device.name());
    if (response_is_exception) resp.faults.push_back("exception");
    if (is(Fault::kCrc) && !on_request) {
      faults_.corrupt(resp.bytes);
      resp.faults.push_back("crc");
    }
    if (is(Fault::kWrongSlave)) {
      resp.bytes[0] = faults_.other_address(resp.bytes[0]);
      reseal(resp.bytes);
      resp.faults.push_back("wrong_slave");
    }
    const bool truncated = is(Fault::kTruncated);
    if (truncated) {
      resp.bytes.resize(faults_.truncated_size(resp.bytes.size()));
      resp.faults.push_back("truncated");
    }
    pause_after = -1;
    if (is(Fault::kPause) && !on_request && resp.bytes.size() >= 2) {
      pause_after = frng.between(0, static_cast<std::int64_t>(resp.bytes.size()) - 2);
      pause = faults_.pause(line());
    }
    const Nanos resp_end = timeline_.emit(std::move(resp), resp_start, [&](std::size_t k) {
      if (static_cast<std::int64_t>(k) == pause_after) return pause;
      return device.inter_char_gap(traffic_, line());
    });
    next_send_ = resp_end + think();
    // After a broken answer the master only gives up when its timeout expires.
    if (truncated) next_send_ = std::max(next_send_, req_end + opt_.master_timeout);
  }

  // Puts a turnaround glitch between the request and the response: either just after the
  // master releases the line or just before the slave drives it. Returns the (possibly
  // later) start of the response.
  Nanos turnaround_burst(Nanos req_end, Nanos resp_start) {
    Rng& frng = faults_.rng();
    TruthRecord burst = noise_record(faults_.turnaround_burst(), "turnaround");
    const Nanos ct = timeline_.char_time();
    const Nanos length = ct * static_cast<Nanos>(burst.bytes.size());
    const Nanos delta = frng.nanos(ct / 2, line().t3_5());
    Nanos burst_start = 0;
    if (frng.chance(0.5)) {
      burst_start = req_end + delta;  // master releases its driver
      resp_start = std::max(resp_start, burst_start + length + ct / 2);
    } else {
      burst_start = resp_start - delta - length;  // slave enables its driver
      if (burst_start < req_end + ct / 2) {
        burst_start = req_end + ct / 2;
        resp_start = burst_start + length + delta;
      }
    }
    timeline_.emit(std::move(burst), burst_start);
    return resp_start;
  }

  const BusOptions& opt_;
  const std::vector<std::unique_ptr<DeviceProfile>>& devices_;
  Timeline timeline_;
  Rng traffic_;
  FaultInjector faults_;
  std::deque<Pending> pending_;
  std::uint64_t txn_ = 0;
  Nanos next_send_ = 0;
};

}  // namespace

Timeline simulate_bus(const BusOptions& options,
                      const std::vector<std::unique_ptr<DeviceProfile>>& devices) {
  return BusSimulator(options, devices).run();
}

}  // namespace rtu::sim
