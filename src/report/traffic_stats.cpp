#include "report/traffic_stats.hpp"

#include <algorithm>

#include "core/chunk.hpp"
#include "core/function_codes.hpp"
#include "dissect/device_stage.hpp"
#include "modbus/data_access.hpp"

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

bool is_damaged(const Record& frame) {
  return !frame.crc_ok || frame.line_errors != 0 || frame.issues.has(IssueId::kTruncated) ||
         frame.issues.has(IssueId::kTooLong) || frame.issues.has(IssueId::kLineError) ||
         frame.issues.has(IssueId::kBreak) || frame.issues.has(IssueId::kOverrun);
}

namespace {

bool has_latency(const Record& response) {
  return response.role == Role::kResponse && response.latency != kUnknownTime &&
         !response.issues.has(IssueId::kWrongSlave) && response.crc_ok;
}

}  // namespace

// The silence before a response is known where its first byte started a read (or every byte
// has its own time): then the latency was seen, to within the timing resolution.
bool counts_latency(const Record& response) {
  return has_latency(response) && response.gap_before != kUnknownTime;
}

bool latency_unseen(const Record& response) {
  return has_latency(response) && response.gap_before == kUnknownTime;
}

void LineErrorCounts::add(std::uint8_t line_errors) {
  ++records;
  if ((line_errors & kParityError) != 0) ++parity;
  if ((line_errors & kFramingError) != 0) ++framing;
  if ((line_errors & kBreak) != 0) ++breaks;
  if ((line_errors & kOverrun) != 0) ++overruns;
}

LineErrorCounts Totals::line_errors_beyond_glitches() const {
  const LineErrorCounts& g = glitch_line_errors;
  return LineErrorCounts{line_error_records - g.records, parity_errors - g.parity,
                         framing_errors - g.framing, breaks - g.breaks, overruns - g.overruns};
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
  issues.merge(o.issues);
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

TrafficStats::TrafficStats(const dissect::DeviceTable* devices) : devices_(devices) {}

void TrafficStats::on_capture(const CaptureInfo& info) {
  set_capture(info);
  echoes_.set_window(info.line.t3_5() + info.timing_resolution);
}

bool TrafficStats::t15_observable() const {
  return info_.resolution_at_end() < info_.line.t1_5();
}

bool TrafficStats::t35_observable() const {
  return info_.resolution_at_end() < info_.line.t3_5();
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

std::uint64_t TrafficStats::all_latencies_unseen() const {
  std::uint64_t n = 0;
  for (const auto& s : slaves_) {
    if (s) n += s->latency_unseen;
  }
  return n;
}

namespace {

RequestKind kind_of(const Record& request, const DataAccess& access) {
  RequestKind k;
  k.slave = request.slave();
  k.function = request.function();
  // The range read, else the one written: FC23 is told apart by what it reads. A mask write
  // (FC22) is listed by its function alone, as RequestKind documents.
  const DataBlock* b = access.read() != nullptr ? access.read() : access.write();
  if (b != nullptr && k.function != fc::kMaskWriteRegister) {
    k.has_range = true;
    k.addr = b->addr;
    k.qty = b->qty;
  }
  return k;
}

// The device stage, where one ran, found what the request accesses already.
RequestKind kind_of(const Record& request) {
  if (request.device != nullptr && request.device->request_access != nullptr) {
    return kind_of(request, *request.device->request_access);
  }
  return kind_of(request, data_access(request, nullptr));
}

// A damaged frame that still reads as a request: an address a request can carry (not a
// broadcast, which expects no answer) and a function a master sends.
bool reads_as_request(const Record& r) {
  const std::uint8_t function = r.function();
  return r.size >= 4 && r.slave() >= 1 && r.slave() <= 247 &&
         (is_public_function(function) || is_user_defined_function(function));
}

// Every field of a RequestKind in one number (8 + 8 + 1 + 16 + 16 bits): equal kinds, equal
// numbers.
std::uint64_t packed(const RequestKind& k) {
  return (std::uint64_t{k.slave} << 41U) | (std::uint64_t{k.function} << 33U) |
         (std::uint64_t{k.has_range} << 32U) | (std::uint64_t{k.addr} << 16U) | k.qty;
}

bool is_glitch(const Record& r) {
  if (r.size == 0 || r.size > 2) return false;
  return std::all_of(r.bytes().begin(), r.bytes().end(),
                     [](std::uint8_t b) { return b == 0x00 || b == 0xFF; });
}

}  // namespace

std::map<RequestKind, RequestKindStats>::iterator TrafficStats::find_kind(const RequestKind& kind) {
  const std::uint64_t key = packed(kind);
  if (const auto* hit = kind_index_.find(key)) return *hit;
  return kinds_.end();
}

std::map<RequestKind, RequestKindStats>::iterator TrafficStats::kind_of_answered(
    const Record& request) {
  if (request.seq == last_request_.seq && request.t_start == last_request_.t_start) {
    return last_request_.kind;
  }
  return find_kind(kind_of(request));
}

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
  totals_.issues.add(r.issues);
  timeline_.at(r.t_start).issues.add(r.issues);
  // The line is busy for exactly size × character time, whatever the timestamps' blur.
  const Nanos busy = static_cast<Nanos>(r.size) * char_time_;
  totals_.busy_ns += static_cast<double>(busy);
  timeline_.spread(r.t_end - busy, r.t_end, [busy](TrafficBucket& b, double share) {
    b.busy_ns += share * static_cast<double>(busy);
  });

  // Noise is sorted first: line errors on a turnaround glitch are not a device's.
  if (r.kind == RecordKind::kNoise) {
    const bool glitch = count_noise(r);
    if (r.line_errors != 0) count_line_errors(r, glitch);
  } else {
    if (r.line_errors != 0) count_line_errors(r, false);
    count_frame(r);
    frame_end_ = r.t_end;
    glitch_span_ = 0;
    if (r.device != nullptr) {
      for (const dissect::PointValue& v : r.device->values) add_point(v);
    }
  }
}

// The silence from the last frame's end to `next`'s start, across the turnaround glitches in
// between (as the framer measures t3.5): the glitch is the line settling while the turnaround
// goes on, so the master's turnaround reads the same on the wire as at the UART pins.
Nanos TrafficStats::silence_since_frame(const Record& next) const {
  if (glitch_span_ == kUnknownTime || next.gap_before == kUnknownTime) return kUnknownTime;
  return glitch_span_ + next.gap_before;
}

// A glitch extends the span from the last frame to its own end; a gap the timestamps blur
// (or no frame before) leaves the span unknown.
void TrafficStats::bridge_glitch(const Record& glitch) {
  const bool known = glitch_span_ != kUnknownTime && glitch.gap_before != kUnknownTime &&
                     frame_end_ != kUnknownTime;
  glitch_span_ = known ? glitch.t_end - frame_end_ : kUnknownTime;
}

void TrafficStats::count_frame(const Record& r) {
  settle_unknown_request(r);
  echoes_.on_frame(r, r.role == Role::kRequest);
  last_sender_ = r.role == Role::kResponse ? std::optional<std::uint8_t>(r.slave()) : std::nullopt;
  TrafficBucket& bucket = timeline_.at(r.t_start);
  ++totals_.frames;
  ++bucket.frames;
  const std::size_t cls = length_class(r.size);
  ++totals_.frames_by_length[cls];
  const bool crc_bad = !r.crc_ok;
  if (crc_bad) {
    ++totals_.crc_by_length[cls];
  } else if (seen_line_error_) {
    ++valid_since_line_error_;
  }

  const bool broadcast = r.slave() == 0 && r.role == Role::kRequest;
  if (!broadcast) {
    SlaveStats& s = slave_mut(r.slave());
    ++s.frames;
    s.bytes += r.size;
    s.issues.add(r.issues);
    ++s.frames_by_length[cls];
    if (crc_bad) {
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
      note_unknown_frame(r);
      previous_ = Previous::kOther;
      break;
  }
}

void TrafficStats::count_request(const Record& r) {
  TrafficBucket& bucket = timeline_.at(r.t_start);
  ++totals_.requests;
  ++bucket.requests;
  const Nanos turnaround = silence_since_frame(r);
  if (previous_ == Previous::kResponse && turnaround != kUnknownTime) {
    master_turnaround_.add(turnaround);
  }
  previous_ = Previous::kRequest;
  if (awaiting_ && awaited_timed_out_) next_request_after_ = r.t_start - awaited_end_;
  const bool timed_out = r.issues.has(IssueId::kTimeout);
  const bool damaged = is_damaged(r);
  if (r.slave() == 0) {
    ++totals_.broadcasts;
    awaiting_.reset();
  } else {
    SlaveStats& s = slave_mut(r.slave());
    ++s.requests;
    if (!damaged) ++s.intact_requests;
    ++s.functions[r.function()];
    if (r.issues.has(IssueId::kT15)) ++s.t15_requests;
    if (r.issues.has(IssueId::kT35)) ++s.t35_requests;
    if (timed_out) count_timeout(r, damaged);
    awaiting_ = r.slave();
    awaited_end_ = r.t_end;
    awaited_timed_out_ = timed_out;
  }

  const RequestKind kind = kind_of(r);
  auto it = find_kind(kind);
  if (it == kinds_.end()) {
    if (kinds_.size() >= kMaxRequestKinds) {
      ++kinds_overflow_;
      return;
    }
    it = kinds_.emplace(kind, RequestKindStats{}).first;
    kind_index_.put(packed(kind), it);
    it->second.first_t = r.t_start;
  } else {
    it->second.period.add(r.t_start - it->second.last_t);
  }
  last_request_ = CountedRequest{r.seq, r.t_start, it};
  RequestKindStats& k = it->second;
  ++k.count;
  k.last_t = r.t_start;
  if (timed_out && !damaged) ++k.timeouts;
}

// The tracker marks every unanswered request `timeout`; which side failed depends on the
// request: the slave ignores one the wire damaged, so only an intact one is its timeout.
void TrafficStats::count_timeout(const Record& request, bool damaged) {
  timed_out_slave_ = request.slave();
  if (damaged) {
    count_damaged_request(request.slave());
    return;
  }
  ++totals_.timeouts;
  ++timeline_.at(request.t_start).timeouts;
  ++slave_mut(request.slave()).timeouts;
}

void TrafficStats::count_damaged_request(std::uint8_t slave) {
  ++totals_.damaged_requests;
  ++slave_mut(slave).damaged_requests;
}

// A damaged frame the tracker could give no role (it fits no length rule) gets no timeout
// verdict either, yet it is often the master's request with a byte lost or garbled. It is
// taken as one when it reads as a request and no answer can still be on its way: none is
// awaited, or the awaited request already timed out and the response timeout has passed
// since it ended (before that, it is more likely that slave's damaged answer).
void TrafficStats::note_unknown_frame(const Record& r) {
  if (!is_damaged(r) || !reads_as_request(r)) return;
  const bool answer_due = awaiting_ && !(awaited_timed_out_ && awaited_end_ != kUnknownTime &&
                                         r.t_start - awaited_end_ > info_.response_timeout);
  if (answer_due) return;
  unknown_request_ = r.slave();
  awaiting_ = r.slave();
  awaited_end_ = r.t_end;
  awaited_timed_out_ = false;
}

// The frame after a damaged request read from an unknown-role frame decides its fate: an
// answer from its slave means the slave read it intact (the damage was at the capture's
// tap); anything else means it went unanswered. At the end of the capture it stays without
// a verdict, as the tracker leaves a request whose timeout has not run out.
void TrafficStats::settle_unknown_request(const Record& next) {
  if (!unknown_request_) return;
  const std::uint8_t slave = *unknown_request_;
  unknown_request_.reset();
  const bool answered = next.role == Role::kResponse && next.slave() == slave;
  if (answered) return;
  count_damaged_request(slave);
  awaiting_.reset();  // the master has moved on: no answer is due any more
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
  if ((unsolicited || wrong_slave) && timed_out_slave_ == r.slave()) {
    ++s.after_next_request;
    if (next_request_after_ != kUnknownTime) s.next_request_after.add(next_request_after_);
  }
  if (latency_unseen(r)) ++s.latency_unseen;
  if (counts_latency(r)) {
    s.latency.add(r.latency);
    for (std::size_t i = 0; i < kCandidateTimeoutsMs.size(); ++i) {
      if (r.latency > kCandidateTimeoutsMs[i] * kNanosPerMilli) ++s.lost_at[i];
    }
  }
  if (r.issues.has(IssueId::kT15)) ++s.t15_responses;
  if (r.issues.has(IssueId::kT35)) ++s.t35_responses;
  if (r.request != nullptr && !wrong_slave) {
    const auto it = kind_of_answered(*r.request);
    if (it != kinds_.end()) {
      ++it->second.responses;
      if (code) {
        ++it->second.exceptions;
        ++it->second.exception_codes[*code];
      }
    }
  }
}

// Every noise record is counted once in the totals and once more in exactly one of: the
// framer's turnaround glitches, the 0x00/0xFF bytes after a turnaround, or the rest (the
// `noise` finding). So the rest's records and bytes are counted over the same records.
// Returns whether `r` is a turnaround glitch of either kind. A glitch keeps the turnaround it
// sits in open (previous_ and the span from the frame before it); other noise ends it.
bool TrafficStats::count_noise(const Record& r) {
  ++totals_.noise_records;
  totals_.noise_bytes += r.size;
  timeline_.at(r.t_start).noise_bytes += r.size;
  bool glitch = true;
  if (r.issues.has(IssueId::kTurnaroundGlitch)) {
    count_turnaround_glitch(r);
  } else if (!count_glitch_after_turnaround(r)) {
    ++other_noise_records_;
    other_noise_bytes_ += r.size;
    glitch = false;
  }
  if (glitch) {
    bridge_glitch(r);
  } else {
    previous_ = Previous::kOther;
    glitch_span_ = kUnknownTime;
  }
  return glitch;
}

// The framer flags a lone byte that follows a frame within about a character: the driver of
// that frame's sender glitching as it releases the line. The sender is the slave when the
// frame was its response, else the master.
void TrafficStats::count_turnaround_glitch(const Record& r) {
  ++totals_.turnaround_glitch_records;
  totals_.turnaround_glitch_bytes += r.size;
  const bool line_error = r.line_errors != 0;
  if (line_error) ++totals_.turnaround_glitch_line_errors;
  if (last_sender_) {
    SlaveStats& s = slave_mut(*last_sender_);
    ++s.turnaround_glitches_sent;
    if (line_error) ++s.turnaround_glitch_line_errors;
  } else {
    ++master_glitches_;
    if (line_error) ++master_glitch_line_errors_;
  }
}

// 0x00/0xFF bytes right after a request or response (a false start bit while nobody drives
// the line); false when `r` is not one.
bool TrafficStats::count_glitch_after_turnaround(const Record& r) {
  if (!is_glitch(r)) return false;
  const bool after_request = previous_ == Previous::kRequest && awaiting_;
  const bool after_response = previous_ == Previous::kResponse;
  if (!after_request && !after_response) return false;
  if (after_request) ++slave_mut(*awaiting_).glitches_after_request;
  if (after_response) ++glitches_after_response_;
  if (r.line_errors != 0) ++glitch_line_errors_;
  for (const std::uint8_t b : r.bytes()) ++(b == 0 ? glitch_00_ : glitch_ff_);
  return true;
}

// Every line-error record counts in the totals and the timeline. One on a turnaround glitch
// is the undriven bus read between two talkers: it blames no slave (that is the glitch
// findings' business) and does not delimit the valid frames "between line errors".
void TrafficStats::count_line_errors(const Record& r, bool glitch) {
  ++totals_.line_error_records;
  if ((r.line_errors & kParityError) != 0) ++totals_.parity_errors;
  if ((r.line_errors & kFramingError) != 0) ++totals_.framing_errors;
  if ((r.line_errors & kBreak) != 0) ++totals_.breaks;
  if ((r.line_errors & kOverrun) != 0) ++totals_.overruns;
  ++timeline_.at(r.t_start).line_errors;
  if (glitch) {
    totals_.glitch_line_errors.add(r.line_errors);
    return;
  }
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

void TrafficStats::add_point(const dissect::PointValue& sample) {
  // The key's top bit is the raw values' own (pointers never set it): the slave goes into the
  // bits below it, which neither kind of key uses.
  const std::uint64_t index_key =
      sample.key == 0 ? 0 : sample.key ^ (std::uint64_t{sample.slave} << 48U);
  if (index_key != 0) {
    if (const PointEntry* hit = point_index_.find(index_key)) {
      update_point((*hit)->second, sample);
      return;
    }
  }
  point_key_.assign(sample.point);
  auto key = std::make_pair(sample.slave, point_key_);
  auto it = points_.find(key);
  if (it == points_.end()) {
    if (points_.size() >= kMaxPoints) {
      ++points_overflow_;
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
  if (index_key != 0) point_index_.put(index_key, it);
  update_point(it->second, sample);
}

void TrafficStats::update_point(PointSeries& p, const dissect::PointValue& sample) {
  if (p.samples > 0 && sample.value != p.last) ++p.changes;
  ++p.samples;
  p.min = std::min(p.min, sample.value);
  p.max = std::max(p.max, sample.value);
  p.last = sample.value;
  p.over_time.at(sample.t).add(sample.value);
}

std::string_view TrafficStats::device_model(std::uint8_t address) const {
  return devices_ == nullptr ? std::string_view{} : devices_->model(address);
}

bool TrafficStats::device_model_identified(std::uint8_t address) const {
  return devices_ != nullptr && devices_->identified(address);
}

bool TrafficStats::device_exception(std::uint8_t address, std::uint8_t code) const {
  return devices_ != nullptr && !devices_->exception_name(address, code).empty();
}

std::string_view TrafficStats::exception_name(std::uint8_t address, std::uint8_t code) const {
  return device_exception(address, code) ? devices_->exception_name(address, code)
                                         : rtu::exception_name(code);
}

}  // namespace rtu
