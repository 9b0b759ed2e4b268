#include "report/traffic_stats.hpp"

#include <algorithm>

#include "core/chunk.hpp"
#include "modbus/function_codes.hpp"

namespace rtu {

std::size_t length_class(std::size_t frame_bytes) {
  if (frame_bytes < 16) return 0;
  if (frame_bytes < 64) return 1;
  if (frame_bytes < 128) return 2;
  return 3;
}

std::string_view length_class_name(std::size_t cls) {
  static constexpr std::array<std::string_view, kLengthClasses> kNames = {"<16", "16-63", "64-127",
                                                                          ">=128"};
  return cls < kNames.size() ? kNames[cls] : "?";
}

double Totals::utilisation() const {
  const Nanos d = duration();
  if (d <= 0) return 0.0;
  return std::min(1.0, busy_ns / static_cast<double>(d));
}

void TrafficBucket::merge(const TrafficBucket& o) {
  frames += o.frames;
  requests += o.requests;
  responses += o.responses;
  crc_errors += o.crc_errors;
  exceptions += o.exceptions;
  timeouts += o.timeouts;
  noise_bytes += o.noise_bytes;
  line_errors += o.line_errors;
  busy_ns += o.busy_ns;
}

void PointBucket::add(double v) {
  if (count == 0) {
    min = v;
    max = v;
  } else {
    min = std::min(min, v);
    max = std::max(max, v);
  }
  last = v;
  ++count;
}

void PointBucket::merge(const PointBucket& o) {
  if (o.count == 0) return;
  if (count == 0) {
    *this = o;
    return;
  }
  min = std::min(min, o.min);
  max = std::max(max, o.max);
  last = o.last;  // `o` is the later bucket of the pair
  count += o.count;
}

TrafficStats::TrafficStats(PointSource* points, PointSink* also)
    : point_source_(points), also_(also) {}

void TrafficStats::on_capture(const CaptureInfo& info) {
  info_ = info;
}

bool TrafficStats::t15_observable() const {
  return info_.timing_resolution < info_.line.t1_5();
}

bool TrafficStats::t35_observable() const {
  return info_.timing_resolution < info_.line.t3_5();
}

SlaveStats& TrafficStats::slave_mut(std::uint8_t address) {
  auto& s = slaves_[address];
  if (!s) s = std::make_unique<SlaveStats>();
  return *s;
}

LogHistogram TrafficStats::all_latencies() const {
  LogHistogram all;
  for (const auto& s : slaves_) {
    if (s) all.merge(s->latency);
  }
  return all;
}

namespace {

RequestKind kind_of(const Record& request) {
  RequestKind k;
  k.slave = request.slave();
  k.function = request.function();
  const auto b = request.bytes();
  auto word = [&](std::size_t i) { return static_cast<std::uint16_t>((b[i] << 8U) | b[i + 1]); };
  switch (k.function) {
    case 0x01:
    case 0x02:
    case 0x03:
    case 0x04:
    case 0x0F:
    case 0x10:
    case 0x17:
      if (b.size() >= 8) {
        k.has_range = true;
        k.addr = word(2);
        k.qty = word(4);
      }
      break;
    case 0x05:
    case 0x06:
      if (b.size() >= 8) {
        k.has_range = true;
        k.addr = word(2);
        k.qty = 1;
      }
      break;
    default: break;
  }
  return k;
}

bool is_glitch(const Record& r) {
  if (r.size == 0 || r.size > 2) return false;
  return std::all_of(r.bytes().begin(), r.bytes().end(),
                     [](std::uint8_t b) { return b == 0x00 || b == 0xFF; });
}

}  // namespace

void TrafficStats::on_record(Record& r) {
  ++totals_.records;
  if (totals_.first_t == kUnknownTime) {
    totals_.first_t = r.t_start;
    totals_.last_t = r.t_end;
    timeline_ = TimeBuckets<TrafficBucket>(r.t_start, kFirstBucketWidth, kTimelineBuckets);
    timeline_started_ = true;
  }
  totals_.last_t = std::max(totals_.last_t, r.t_end);
  totals_.bytes += r.size;
  // The line is busy for exactly size × character time, whatever the timestamps' blur.
  const Nanos busy = static_cast<Nanos>(r.size) * info_.line.char_time();
  totals_.busy_ns += static_cast<double>(busy);
  timeline_.spread(r.t_end - busy, r.t_end, [busy](TrafficBucket& b, double share) {
    b.busy_ns += share * static_cast<double>(busy);
  });

  if (r.line_errors != 0) count_line_errors(r);
  if (r.kind == RecordKind::kNoise) {
    count_noise(r);
  } else {
    count_frame(r);
    if (point_source_ != nullptr) point_source_->extract(r, *this);
  }
}

void TrafficStats::count_frame(const Record& r) {
  TrafficBucket& bucket = timeline_.at(r.t_start);
  ++totals_.frames;
  ++bucket.frames;
  const std::size_t cls = length_class(r.size);
  ++totals_.frames_by_length[cls];
  const bool crc_bad = !r.crc_ok;
  if (crc_bad) {
    ++totals_.crc_errors;
    ++totals_.crc_by_length[cls];
    ++bucket.crc_errors;
  } else if (seen_line_error_) {
    ++valid_since_line_error_;
  }
  if (r.issues.has(IssueId::kT15)) ++totals_.t15_frames;
  if (r.issues.has(IssueId::kT35)) ++totals_.t35_frames;

  const bool broadcast = r.slave() == 0 && r.role == Role::kRequest;
  if (!broadcast) {
    SlaveStats& s = slave_mut(r.slave());
    ++s.frames;
    s.bytes += r.size;
    ++s.frames_by_length[cls];
    if (crc_bad) {
      ++s.crc_errors;
      ++s.crc_by_length[cls];
    } else {
      ++s.valid_frames;
    }
  }

  switch (r.role) {
    case Role::kRequest: count_request(r); break;
    case Role::kResponse: count_response(r); break;
    case Role::kUnknown:
      ++totals_.unknown_role;
      previous_ = Previous::kOther;
      break;
  }
}

void TrafficStats::count_request(const Record& r) {
  TrafficBucket& bucket = timeline_.at(r.t_start);
  ++totals_.requests;
  ++bucket.requests;
  if (previous_ == Previous::kResponse && r.gap_before != kUnknownTime) {
    master_turnaround_.add(r.gap_before);
  }
  previous_ = Previous::kRequest;
  const bool timed_out = r.issues.has(IssueId::kTimeout);
  if (r.slave() == 0) {
    ++totals_.broadcasts;
    awaiting_.reset();
  } else {
    SlaveStats& s = slave_mut(r.slave());
    ++s.requests;
    ++s.functions[r.function()];
    if (r.issues.has(IssueId::kT15)) ++s.t15_requests;
    if (r.issues.has(IssueId::kT35)) ++s.t35_requests;
    if (timed_out) {
      ++totals_.timeouts;
      ++bucket.timeouts;
      ++s.timeouts;
      timed_out_slave_ = r.slave();
    }
    awaiting_ = r.slave();
  }

  const RequestKind kind = kind_of(r);
  auto it = kinds_.find(kind);
  if (it == kinds_.end()) {
    if (kinds_.size() >= kMaxRequestKinds) {
      ++kinds_overflow_;
      return;
    }
    it = kinds_.emplace(kind, RequestKindStats{}).first;
    it->second.first_t = r.t_start;
  } else {
    it->second.period.add(r.t_start - it->second.last_t);
  }
  RequestKindStats& k = it->second;
  ++k.count;
  k.last_t = r.t_start;
  if (timed_out) ++k.timeouts;
}

void TrafficStats::count_response(const Record& r) {
  TrafficBucket& bucket = timeline_.at(r.t_start);
  ++totals_.responses;
  ++bucket.responses;
  previous_ = Previous::kResponse;
  awaiting_.reset();
  SlaveStats& s = slave_mut(r.slave());
  ++s.responses;
  const bool unsolicited = r.issues.has(IssueId::kUnsolicited);
  const bool wrong_slave = r.issues.has(IssueId::kWrongSlave);
  std::optional<std::uint8_t> code;
  if (r.is_exception() && r.size >= 3) {
    code = r.bytes()[2];
    ++totals_.exceptions;
    ++bucket.exceptions;
    ++s.exceptions;
    ++s.exception_codes[*code];
  }
  if (r.issues.has(IssueId::kLate)) {
    ++totals_.late;
    ++s.late;
  }
  if (unsolicited) {
    ++totals_.unsolicited;
    ++s.unsolicited;
  }
  if (wrong_slave) {
    ++totals_.wrong_slave;
    ++s.wrong_slave;
  }
  if ((unsolicited || wrong_slave) && timed_out_slave_ == r.slave()) ++s.after_next_request;
  if (r.latency != kUnknownTime && !wrong_slave && r.crc_ok) {
    s.latency.add(r.latency);
    for (std::size_t i = 0; i < kCandidateTimeoutsMs.size(); ++i) {
      if (r.latency > kCandidateTimeoutsMs[i] * kNanosPerMilli) ++s.lost_at[i];
    }
  }
  if (r.issues.has(IssueId::kT15)) ++s.t15_responses;
  if (r.issues.has(IssueId::kT35)) ++s.t35_responses;
  if (r.request != nullptr && !wrong_slave) {
    auto it = kinds_.find(kind_of(*r.request));
    if (it != kinds_.end()) {
      ++it->second.responses;
      if (code) {
        ++it->second.exceptions;
        ++it->second.exception_codes[*code];
      }
    }
  }
}

void TrafficStats::count_noise(const Record& r) {
  ++totals_.noise_records;
  totals_.noise_bytes += r.size;
  timeline_.at(r.t_start).noise_bytes += r.size;
  if (is_glitch(r)) {
    const bool after_request = previous_ == Previous::kRequest && awaiting_;
    const bool after_response = previous_ == Previous::kResponse;
    if (after_request) ++slave_mut(*awaiting_).glitches_after_request;
    if (after_response) ++glitches_after_response_;
    if (after_request || after_response) {
      for (const std::uint8_t b : r.bytes()) ++(b == 0 ? glitch_00_ : glitch_ff_);
    }
  }
  previous_ = Previous::kOther;
}

void TrafficStats::count_line_errors(const Record& r) {
  ++totals_.line_error_records;
  if ((r.line_errors & kParityError) != 0) ++totals_.parity_errors;
  if ((r.line_errors & kFramingError) != 0) ++totals_.framing_errors;
  if ((r.line_errors & kBreak) != 0) ++totals_.breaks;
  if ((r.line_errors & kOverrun) != 0) ++totals_.overruns;
  ++timeline_.at(r.t_start).line_errors;
  if (r.kind == RecordKind::kFrame && r.slave() != 0) {
    ++slave_mut(r.slave()).line_errors;
  } else if (awaiting_) {
    ++slave_mut(*awaiting_).line_errors;
  } else {
    ++line_errors_unattributed_;
  }
  seen_line_error_ = true;
  totals_.valid_frames_between_line_errors = valid_since_line_error_;
}

void TrafficStats::on_point(const PointSample& sample) {
  point_key_.assign(sample.point);
  auto key = std::make_pair(sample.slave, point_key_);
  auto it = points_.find(key);
  if (it == points_.end()) {
    if (points_.size() >= kMaxPoints) {
      ++points_overflow_;
      if (also_ != nullptr) also_->on_point(sample);
      return;
    }
    PointSeries series{std::string(sample.unit),
                       0,
                       0,
                       sample.value,
                       sample.value,
                       sample.value,
                       sample.value,
                       TimeBuckets<PointBucket>(totals_.first_t, kFirstBucketWidth, kPointBuckets)};
    it = points_.emplace(std::move(key), std::move(series)).first;
  }
  PointSeries& p = it->second;
  if (p.samples > 0 && sample.value != p.last) ++p.changes;
  ++p.samples;
  p.min = std::min(p.min, sample.value);
  p.max = std::max(p.max, sample.value);
  p.last = sample.value;
  p.over_time.at(sample.t).add(sample.value);
  if (also_ != nullptr) also_->on_point(sample);
}

std::string_view TrafficStats::device_model(std::uint8_t address) const {
  return point_source_ == nullptr ? std::string_view{} : point_source_->device_model(address);
}

bool TrafficStats::device_model_identified(std::uint8_t address) const {
  return !device_model(address).empty() && point_source_->device_model_identified(address);
}

bool TrafficStats::device_exception(std::uint8_t address, std::uint8_t code) const {
  return point_source_ != nullptr && !point_source_->device_exception_name(address, code).empty();
}

std::string_view TrafficStats::exception_name(std::uint8_t address, std::uint8_t code) const {
  return device_exception(address, code) ? point_source_->device_exception_name(address, code)
                                         : rtu::exception_name(code);
}

}  // namespace rtu
