#include "bus_simulator.hpp"

#include <algorithm>
#include <deque>
#include <utility>

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
      if (opt_.profile == FaultProfile::kHeavy) {
        heavy_transaction(*p.device, std::move(p.exchange));
      } else {
        transaction(*p.device, std::move(p.exchange));
      }
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

  // The heavy profile's transaction. Each fault works on one stage (what is sent, when,
  // what surrounds it), so two faults of one transaction combine; a two-sided fault picks
  // the request or the response for itself.
  void heavy_transaction(DeviceProfile& device, Exchange ex) {
    const std::vector<Fault> faults = faults_.draw_heavy();
    const auto is = [&](Fault f) {
      return std::find(faults.begin(), faults.end(), f) != faults.end();
    };
    const std::uint64_t txn = ++txn_;
    Rng& frng = faults_.rng();

    std::string_view device_name = device.name();
    if (is(Fault::kException)) ex = device.provoke_exception(frng);
    const bool broadcast = is(Fault::kBroadcast);
    if (broadcast) {
      ex.request = device.broadcast_write(frng);
      ex.response.reset();
    } else if (is(Fault::kDeadSlave)) {
      const auto quantity = static_cast<std::uint16_t>(frng.between(1, 10));
      ex.request = read_request(faults_.absent_address(addresses()), 0x03,
                                static_cast<std::uint16_t>(frng.below(0x1000)), quantity);
      ex.response.reset();
      device_name = "absent";
    }
    const bool has_response = ex.response.has_value();
    // Which side each two-sided fault hits: the request, or the response when there is
    // one. Drawn for every kind, so a fault's side does not depend on what came with it.
    const auto side = [&](Fault f) {
      const bool request_side = !has_response || frng.chance(0.5);
      return std::pair{is(f) && request_side, is(f) && !request_side};
    };
    const auto [flip_req, flip_resp] = side(Fault::kBitflip);
    const auto [cut_req, cut_resp] = side(Fault::kTruncated);
    const auto [before_req, before_resp] = side(Fault::kNoiseBefore);
    const auto [after_req, after_resp] = side(Fault::kNoiseAfter);
    const auto [pause_req, pause_resp] = side(Fault::kPause);
    const auto [short_req, short_resp] = side(Fault::kShortGap);

    TruthRecord request = frame_record(ex.request, TruthRole::kRequest, txn, device_name);
    if (broadcast) request.faults.push_back("broadcast");
    bool answered = has_response;
    Bytes response = answered ? std::move(*ex.response) : Bytes{};
    bool response_is_exception = is(Fault::kException);
    if (flip_req) {
      request.flipped = faults_.flip_bits(request.bytes);
      request.faults.push_back("crc");
      answered = false;
      if (auto reply = device.answer_to_bad_crc(request.bytes)) {
        answered = true;
        response = std::move(*reply);
      }
      response_is_exception = answered;
    }
    if (cut_req) {
      request.intended_size = request.bytes.size();
      request.bytes.resize(faults_.truncated_size(request.bytes.size()));
      request.faults.push_back("truncated");
      answered = false;  // a slave ignores a request it did not receive whole
    }
    if (is(Fault::kTimeout)) answered = false;
    if (!answered && !broadcast) request.faults.push_back("timeout");

    Nanos start = next_send_;
    if (short_req && !timeline_.records().empty()) {
      start = timeline_.wire_end() + faults_.short_gap(line());
    }
    if (before_req) start = noise_before(start);
    std::int64_t pause_after = -1;  // index of the byte followed by a pause, or -1
    Nanos pause = 0;
    if (pause_req && request.bytes.size() >= 2) {
      pause_after = frng.between(0, static_cast<std::int64_t>(request.bytes.size()) - 2);
      pause = faults_.pause(line());
    }
    const Nanos req_end = timeline_.emit(std::move(request), start, [&](std::size_t k) {
      return static_cast<std::int64_t>(k) == pause_after ? pause : Nanos{0};
    });

    if (!answered) {
      if (after_req) noise_after();
      if (is(Fault::kGlitch)) glitch();
      next_send_ = broadcast ? req_end + 50 * kNanosPerMilli : req_end + opt_.master_timeout;
      next_send_ = std::max(next_send_, timeline_.wire_end() + think());
      return;
    }

    Nanos resp_start = req_end + line().t3_5() + device.turnaround(traffic_);
    if (is(Fault::kFastResponse)) {
      resp_start = req_end + faults_.fast_gap(line());
    } else if (short_resp) {
      resp_start = req_end + faults_.short_gap(line());
    }
    if (is(Fault::kTurnaround)) resp_start = turnaround_burst(req_end, resp_start);
    if (after_req) {
      // Touches the request only: the response keeps at least t3.5 away from it.
      const Nanos end = noise_after();
      resp_start = std::max(resp_start, end + line().t3_5() + timeline_.char_time());
    }
    if (is(Fault::kNoiseGap)) {
      TruthRecord burst = noise_record(faults_.noise_burst(), "burst");
      const Nanos end =
          timeline_.emit(std::move(burst), timeline_.wire_end() + faults_.touching_gap(line()));
      resp_start = end + faults_.touching_gap(line());
    }
    resp_start = std::max(resp_start, timeline_.wire_end());
    if (before_resp) resp_start = noise_before(resp_start);

    TruthRecord resp = frame_record(std::move(response), TruthRole::kResponse, txn, device_name);
    if (response_is_exception) resp.faults.push_back("exception");
    if (is(Fault::kWrongSlave)) {
      resp.bytes[0] = faults_.other_address(resp.bytes[0]);
      reseal(resp.bytes);
      resp.faults.push_back("wrong_slave");
    }
    if (flip_resp) {
      resp.flipped = faults_.flip_bits(resp.bytes);
      resp.faults.push_back("crc");
    }
    if (cut_resp) {
      resp.intended_size = resp.bytes.size();
      resp.bytes.resize(faults_.truncated_size(resp.bytes.size()));
      resp.faults.push_back("truncated");
    }
    pause_after = -1;
    if (pause_resp && resp.bytes.size() >= 2) {
      pause_after = frng.between(0, static_cast<std::int64_t>(resp.bytes.size()) - 2);
      pause = faults_.pause(line());
    }
    timeline_.emit(std::move(resp), resp_start, [&](std::size_t k) {
      if (static_cast<std::int64_t>(k) == pause_after) return pause;
      return device.inter_char_gap(traffic_, line());
    });
    if (is(Fault::kGlitch)) glitch();
    if (after_resp) noise_after();
    next_send_ = timeline_.wire_end() + think();
    // After a broken answer the master only gives up when its timeout expires.
    if (cut_resp) next_send_ = std::max(next_send_, req_end + opt_.master_timeout);
  }

  // A noise burst that ends less than t3.5 before `start` (the frame it touches), and at
  // least t3.5 after the previous record, so it touches one frame only. Returns the start
  // of that frame, later than `start` when the burst did not fit before it.
  Nanos noise_before(Nanos start) {
    TruthRecord burst = noise_record(faults_.noise_burst(), "burst");
    const Nanos gap = faults_.touching_gap(line());
    const Nanos length = timeline_.char_time() * static_cast<Nanos>(burst.bytes.size());
    const Nanos floor =
        timeline_.records().empty() ? Nanos{0} : timeline_.wire_end() + line().t3_5();
    const Nanos at = std::max(start - gap - length, floor);
    return timeline_.emit(std::move(burst), at) + gap;
  }

  // A noise burst less than t3.5 after the last record. Returns its end.
  Nanos noise_after() {
    TruthRecord burst = noise_record(faults_.noise_burst(), "burst");
    return timeline_.emit(std::move(burst), timeline_.wire_end() + faults_.touching_gap(line()));
  }

  // One glitch byte 50-150 us after the last record (an RS-485 driver released right
  // after the frame's last stop bit). Returns its end.
  Nanos glitch() {
    TruthRecord g = noise_record(Bytes{faults_.glitch_byte()}, "glitch");
    return timeline_.emit(std::move(g), timeline_.wire_end() + faults_.glitch_delay());
  }

  [[nodiscard]] std::vector<std::uint8_t> addresses() const {
    std::vector<std::uint8_t> out;
    for (const auto& d : devices_) out.push_back(d->address());
    return out;
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
