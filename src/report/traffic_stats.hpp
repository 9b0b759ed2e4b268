#pragma once
// The statistics behind `rtuscope report`: a RecordSink that folds a capture of any length
// into bounded tables. Memory is fixed by the limits below, never by the capture's length:
//   - per slave: at most 256 addresses (the address is a byte), each with a LogHistogram of
//     latencies and small fixed counters;
//   - per request kind (slave, function, start address, quantity): at most kMaxRequestKinds,
//     further kinds counted in request_kinds_overflow();
//   - per point (slave, point name): at most kMaxPoints series, further ones counted in
//     points_overflow();
//   - over time: kTimelineBuckets buckets (and kPointBuckets per point) that merge pairwise
//     as the capture grows (TimeBuckets).
// Findings are computed from these numbers afterwards (findings.hpp).
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>

#include "core/flat_index.hpp"
#include "dissect/device_table.hpp"
#include "dissect/point_value.hpp"
#include "framing/capture_info.hpp"
#include "framing/record.hpp"
#include "report/identification_sample.hpp"
#include "report/log_histogram.hpp"
#include "report/request_echoes.hpp"
#include "report/time_buckets.hpp"

namespace rtu {

// Master response timeouts tried against each slave's observed latencies ("a timeout of
// 250 ms would have lost 0.4% of the responses").
inline constexpr std::array<std::int64_t, 14> kCandidateTimeoutsMs = {
    50, 100, 150, 200, 250, 300, 400, 500, 750, 1000, 1500, 2000, 3000, 5000};

// Frame-length classes for CRC error rates: < 16, 16-63, 64-127, ≥ 128 bytes.
inline constexpr std::size_t kLengthClasses = 4;
std::size_t length_class(std::size_t frame_bytes);
std::string_view length_class_name(std::size_t cls);  // "<16", "16-63", ...

// Whether the wire damaged a frame (bad CRC, truncated, too long, parity/framing/break/
// overrun on its bytes): a slave's receiver drops such a request instead of answering it.
bool is_damaged(const Record& frame);

// Whether a response's latency counts in its slave's latency statistics: a measured latency
// on an intact response from the slave that was asked, whose start the capture shows. The
// report and the metrics share it.
bool counts_latency(const Record& response);
// An intact response from the slave that was asked whose latency the capture cannot show: it
// came in the same read as the end of its request (an adapter's batching), so its bytes were
// placed back to back with the request's and its latency reads 0, a lower bound only. It is
// counted apart, not as a latency of 0.
bool latency_unseen(const Record& response);

// Records with parity/framing/break/overrun errors, and which errors they carry.
struct LineErrorCounts {
  std::uint64_t records = 0;
  std::uint64_t parity = 0;
  std::uint64_t framing = 0;
  std::uint64_t breaks = 0;
  std::uint64_t overruns = 0;
  void add(std::uint8_t line_errors);  // one record's LineError bits
};

struct Totals {
  Nanos first_t = kUnknownTime;  // start of the first record
  Nanos last_t = kUnknownTime;   // end of the last record
  std::uint64_t records = 0;
  std::uint64_t frames = 0;
  std::uint64_t requests = 0;
  std::uint64_t responses = 0;
  std::uint64_t unknown_role = 0;  // frames neither request nor response (e.g. bad CRC)
  std::uint64_t broadcasts = 0;
  std::uint64_t bytes = 0;  // every byte on the line, noise included
  std::uint64_t noise_records = 0;
  std::uint64_t noise_bytes = 0;
  // Records carrying each issue key, device keys included (crc, late, t1.5, scale_unknown...).
  IssueCounts issues;
  std::uint64_t exceptions = 0;
  std::uint64_t timeouts = 0;          // intact requests that got no answer (SlaveStats)
  std::uint64_t damaged_requests = 0;  // damaged requests that got no answer (SlaveStats)
  // Noise records the framer flagged `turnaround_glitch`, and their bytes (part of noise_*).
  std::uint64_t turnaround_glitch_records = 0;
  std::uint64_t turnaround_glitch_bytes = 0;
  std::uint64_t turnaround_glitch_line_errors = 0;  // of those records, ones with line errors
  std::uint64_t line_error_records = 0;             // records with any parity/framing/break/overrun
  std::uint64_t parity_errors = 0;                  // records with a parity error (and so on)
  std::uint64_t framing_errors = 0;
  std::uint64_t breaks = 0;
  std::uint64_t overruns = 0;
  // Of the line-error records above, those on turnaround glitches of either kind (flagged by
  // the framer, or lone 0x00/0xFF bytes after a turnaround): the undriven line read while
  // nobody holds it, not a device's line settings, so the line-error findings leave them out.
  LineErrorCounts glitch_line_errors;
  double busy_ns = 0.0;  // bytes × character time
  std::array<std::uint64_t, kLengthClasses> frames_by_length{};
  std::array<std::uint64_t, kLengthClasses> crc_by_length{};
  // Line errors "with valid frames in between": CRC-valid frames seen after the first line
  // error and before the last one (line errors on turnaround glitches aside).
  std::uint64_t valid_frames_between_line_errors = 0;

  // The line-error records that are not turnaround glitches: what can point at a device's
  // baud rate or parity.
  [[nodiscard]] LineErrorCounts line_errors_beyond_glitches() const;
  [[nodiscard]] Nanos duration() const { return first_t == kUnknownTime ? 0 : last_t - first_t; }
  [[nodiscard]] double utilisation() const;  // 0..1
};

struct SlaveStats {
  std::uint64_t requests = 0;         // requests addressed to this slave
  std::uint64_t intact_requests = 0;  // of those, the ones with no damage (is_damaged)
  std::uint64_t responses = 0;        // responses from this slave
  std::uint64_t exceptions = 0;
  // Intact requests to it that got no response in time: the slave's own failures.
  std::uint64_t timeouts = 0;
  // Requests to it that the wire had damaged (bad CRC, truncated, line errors) and that got
  // no answer: a slave rightly ignores such a request, so these are not its timeouts. They
  // include damaged frames whose role the tracker left unknown but that read as a request
  // from the master (see TrafficStats::note_unknown_frame).
  std::uint64_t damaged_requests = 0;
  // Its frames (requests to it and its responses) carrying each issue key: crc, late,
  // unsolicited, wrong_slave (its responses to a request for another slave), device keys...
  IssueCounts issues;
  // Its responses that came after the master had given up and sent the next request.
  std::uint64_t after_next_request = 0;
  // For those: how long after its request ended the next request began. One master gives
  // up after its timeout, always about as long; a second master's requests fall anywhere.
  LogHistogram next_request_after;
  std::uint64_t frames = 0;
  std::uint64_t valid_frames = 0;  // CRC ok
  std::uint64_t bytes = 0;
  std::map<std::uint8_t, std::uint64_t> exception_codes;
  std::map<std::uint8_t, std::uint64_t> functions;  // request function codes used
  LogHistogram latency;
  std::uint64_t latency_unseen = 0;  // answers whose latency the capture cannot show
  std::array<std::uint64_t, kCandidateTimeoutsMs.size()> lost_at{};  // latency > candidate
  std::uint64_t t15_requests = 0;   // requests to it with a pause > t1.5 inside
  std::uint64_t t15_responses = 0;  // its responses with a pause > t1.5 inside
  std::uint64_t t35_responses = 0;  // its responses starting < t3.5 after the request
  std::uint64_t t35_requests = 0;   // requests to it starting < t3.5 after the previous frame
  // Single 0x00/0xFF noise bytes right after a request to it (its turnaround).
  std::uint64_t glitches_after_request = 0;
  // Noise flagged `turnaround_glitch` right after one of its responses: its own driver.
  std::uint64_t turnaround_glitches_sent = 0;
  std::uint64_t turnaround_glitch_line_errors = 0;  // of those, the ones with line errors
  // Records with line errors while its answer was awaited, or carrying its address; line
  // errors on turnaround glitches are left out (Totals::glitch_line_errors).
  std::uint64_t line_errors = 0;
  std::array<std::uint64_t, kLengthClasses> frames_by_length{};
  std::array<std::uint64_t, kLengthClasses> crc_by_length{};
};

struct RequestKind {
  std::uint8_t slave = 0;
  std::uint8_t function = 0;
  bool has_range = false;  // addr/qty meaningful (FC01-06, 15, 16, 23)
  std::uint16_t addr = 0;
  std::uint16_t qty = 0;
  auto operator<=>(const RequestKind&) const = default;
};

struct RequestKindStats {
  std::uint64_t count = 0;
  std::uint64_t responses = 0;
  std::uint64_t exceptions = 0;
  std::uint64_t timeouts = 0;
  std::map<std::uint8_t, std::uint64_t> exception_codes;
  Nanos first_t = 0;
  Nanos last_t = 0;
  LogHistogram period;  // between consecutive requests of this kind
};

struct TrafficBucket {
  std::uint64_t frames = 0;
  std::uint64_t requests = 0;
  std::uint64_t responses = 0;
  IssueCounts issues;  // records starting in the bucket, per issue key
  std::uint64_t exceptions = 0;
  std::uint64_t timeouts = 0;
  std::uint64_t noise_bytes = 0;
  std::uint64_t line_errors = 0;
  double busy_ns = 0.0;
  void merge(const TrafficBucket& o);
};

struct PointBucket {
  std::uint64_t count = 0;
  double min = 0.0;
  double max = 0.0;
  double last = 0.0;
  void add(double v);
  void merge(const PointBucket& o);
};

struct PointSeries {
  std::string unit;
  std::uint64_t samples = 0;
  std::uint64_t changes = 0;  // samples whose value differs from the previous one
  double first = 0.0;
  double min = 0.0;
  double max = 0.0;
  double last = 0.0;
  TimeBuckets<PointBucket> over_time;
};

class TrafficStats : public RecordSink {
 public:
  static constexpr std::size_t kMaxRequestKinds = 512;
  static constexpr std::size_t kMaxPoints = 1024;
  static constexpr std::size_t kTimelineBuckets = 240;
  static constexpr std::size_t kPointBuckets = 120;
  static constexpr Nanos kFirstBucketWidth = kNanosPerMilli;

  // Register values come from the records (the device stage's DeviceReading::values).
  // `devices` (optional, not owned) tells the slaves' models when the report is written.
  explicit TrafficStats(const dissect::DeviceTable* devices = nullptr);

  void on_capture(const CaptureInfo& info) override;
  void on_record(Record& record) override;
  // The capture's description once the whole capture was decoded: the same settings as
  // on_capture gave, now with the resolution the reads showed while decoding
  // (CaptureInfo::learned_resolution), and, where it was surveyed while being decoded
  // (decode_and_survey), the warnings and the per-byte timing only the whole capture tells.
  void complete_capture(const CaptureInfo& info) { set_capture(info); }
  // What identification looked at, where it ran (the models it named are in the devices).
  void note_identification(const IdentificationSample& sample) { identification_ = sample; }

  [[nodiscard]] const CaptureInfo& capture() const { return info_; }
  [[nodiscard]] const std::optional<IdentificationSample>& identification() const {
    return identification_;
  }
  [[nodiscard]] const Totals& totals() const { return totals_; }
  // Slaves seen, by address; null for addresses never seen.
  [[nodiscard]] const SlaveStats* slave(std::uint8_t address) const {
    return slaves_[address].get();
  }
  [[nodiscard]] const std::map<RequestKind, RequestKindStats>& request_kinds() const {
    return kinds_;
  }
  [[nodiscard]] std::uint64_t request_kinds_overflow() const { return kinds_overflow_; }
  [[nodiscard]] const TimeBuckets<TrafficBucket>& timeline() const { return timeline_; }
  [[nodiscard]] const std::map<std::pair<std::uint8_t, std::string>, PointSeries>& points() const {
    return points_;
  }
  [[nodiscard]] std::uint64_t points_overflow() const { return points_overflow_; }
  // What the device table knows about a slave's device at the time of asking (a live run
  // identifies models only after the last record): its model ("" when unknown), whether it
  // was identified rather than configured, and an exception code's meaning (the device's
  // own where its map has one, else the standard one; `device_exception` says which).
  [[nodiscard]] std::string_view device_model(std::uint8_t address) const;
  [[nodiscard]] bool device_model_identified(std::uint8_t address) const;
  [[nodiscard]] bool device_exception(std::uint8_t address, std::uint8_t code) const;
  [[nodiscard]] std::string_view exception_name(std::uint8_t address, std::uint8_t code) const;
  // Silence from a response's end to the master's next request (where observable), turnaround
  // glitches in between included.
  [[nodiscard]] const LogHistogram& master_turnaround() const { return master_turnaround_; }
  // Latencies of every slave together.
  [[nodiscard]] LogHistogram all_latencies() const;
  [[nodiscard]] std::uint64_t all_latencies_unseen() const;
  // Single 0x00/0xFF noise bytes right after a response (the master's turnaround).
  [[nodiscard]] std::uint64_t glitches_after_response() const { return glitches_after_response_; }
  [[nodiscard]] std::uint64_t glitch_bytes_00() const { return glitch_00_; }
  [[nodiscard]] std::uint64_t glitch_bytes_ff() const { return glitch_ff_; }
  // Of those 0x00/0xFF glitches, the ones with line errors (a 0x00 with a framing error is
  // the undriven line read as a break).
  [[nodiscard]] std::uint64_t glitches_after_turnaround_line_errors() const {
    return glitch_line_errors_;
  }
  // Line-error records with nobody's answer awaited and no slave address to blame.
  [[nodiscard]] std::uint64_t line_errors_unattributed() const { return line_errors_unattributed_; }
  // Noise flagged `turnaround_glitch` right after a frame the master sent.
  [[nodiscard]] std::uint64_t master_turnaround_glitches() const { return master_glitches_; }
  [[nodiscard]] std::uint64_t master_turnaround_glitch_line_errors() const {
    return master_glitch_line_errors_;
  }
  // Noise that neither kind of turnaround glitch explains: what the `noise` finding is about.
  // Records and bytes are counted over the same records, as in Totals::noise_*.
  [[nodiscard]] std::uint64_t unexplained_noise_records() const { return other_noise_records_; }
  [[nodiscard]] std::uint64_t unexplained_noise_bytes() const { return other_noise_bytes_; }

  // Whether the capture's timestamps can show pauses of t1.5 / t3.5.
  [[nodiscard]] bool t15_observable() const;
  [[nodiscard]] bool t35_observable() const;
  [[nodiscard]] const RequestEchoes& request_echoes() const { return echoes_; }

 private:
  void add_point(const dissect::PointValue& value);
  void update_point(PointSeries& series, const dissect::PointValue& value);
  SlaveStats& slave_mut(std::uint8_t address);
  void count_frame(const Record& r);
  void count_request(const Record& r);
  void count_response(const Record& r);
  void count_timeout(const Record& request, bool damaged);
  void count_damaged_request(std::uint8_t slave);
  void note_unknown_frame(const Record& r);
  void settle_unknown_request(const Record& next);
  bool count_noise(const Record& r);
  void count_turnaround_glitch(const Record& r);
  bool count_glitch_after_turnaround(const Record& r);
  void count_line_errors(const Record& r, bool glitch);
  [[nodiscard]] Nanos silence_since_frame(const Record& next) const;
  void bridge_glitch(const Record& glitch);

  const dissect::DeviceTable* devices_;
  // The capture's description and what each record needs of it, set together.
  void set_capture(const CaptureInfo& info) {
    info_ = info;
    char_time_ = info.line.char_time();
  }
  CaptureInfo info_;
  // info_.line.char_time(), kept: it divides, and each record's busy time needs it.
  Nanos char_time_ = info_.line.char_time();
  std::optional<IdentificationSample> identification_;
  Totals totals_;
  std::array<std::unique_ptr<SlaveStats>, 256> slaves_{};
  std::map<RequestKind, RequestKindStats> kinds_;
  std::uint64_t kinds_overflow_ = 0;
  // RequestKind packed into 64 bits → its entry in kinds_: found by hashing, not by a walk
  // down the tree at every request and response. std::map entries never move.
  FlatIndex<std::map<RequestKind, RequestKindStats>::iterator> kind_index_;
  std::map<RequestKind, RequestKindStats>::iterator find_kind(const RequestKind& kind);
  // The kind entry of the request counted last, found again for its response without
  // decoding the request a second time (one master asks one question at a time, so the
  // response nearly always follows the request it answers).
  struct CountedRequest {
    std::uint64_t seq = UINT64_MAX;
    Nanos t_start = kUnknownTime;
    std::map<RequestKind, RequestKindStats>::iterator kind;
  };
  CountedRequest last_request_;
  std::map<RequestKind, RequestKindStats>::iterator kind_of_answered(const Record& request);
  TimeBuckets<TrafficBucket> timeline_{0, kFirstBucketWidth, kTimelineBuckets};
  bool timeline_started_ = false;
  std::map<std::pair<std::uint8_t, std::string>, PointSeries> points_;
  std::uint64_t points_overflow_ = 0;
  std::string point_key_;  // reused lookup key
  // (slave, PointValue::key) → its series in points_, so a sample finds its series without
  // comparing names. std::map entries never move.
  using PointEntry = std::map<std::pair<std::uint8_t, std::string>, PointSeries>::iterator;
  FlatIndex<PointEntry> point_index_;
  LogHistogram master_turnaround_;
  RequestEchoes echoes_;

  // What the previous record was, for turnaround and attribution. A turnaround glitch leaves
  // it unchanged: the line settling inside a turnaround is not the next record of traffic.
  enum class Previous : std::uint8_t { kNothing, kRequest, kResponse, kOther };
  Previous previous_ = Previous::kNothing;
  // End of the last frame, and the time from it to the end of the turnaround glitches after
  // it (0 when a frame was the last record; kUnknownTime when a gap in between is blurred).
  Nanos frame_end_ = kUnknownTime;
  Nanos glitch_span_ = kUnknownTime;
  std::optional<std::uint8_t> awaiting_;         // slave whose answer is expected
  Nanos awaited_end_ = kUnknownTime;             // end of the request that set awaiting_
  bool awaited_timed_out_ = false;               // the tracker's verdict on that request
  Nanos next_request_after_ = kUnknownTime;      // from a timed-out request to the next one
  std::optional<std::uint8_t> timed_out_slave_;  // last request that timed out
  // A damaged unknown-role frame read as the master's request to this slave; whether it was
  // answered is known at the next frame.
  std::optional<std::uint8_t> unknown_request_;
  // Who sent the last frame: a slave (its response) or, when empty, the master.
  std::optional<std::uint8_t> last_sender_;
  std::uint64_t master_glitches_ = 0;
  std::uint64_t master_glitch_line_errors_ = 0;
  std::uint64_t other_noise_records_ = 0;
  std::uint64_t other_noise_bytes_ = 0;
  std::uint64_t glitches_after_response_ = 0;
  std::uint64_t glitch_00_ = 0;
  std::uint64_t glitch_ff_ = 0;
  std::uint64_t glitch_line_errors_ = 0;
  std::uint64_t line_errors_unattributed_ = 0;
  std::uint64_t valid_since_line_error_ = 0;
  bool seen_line_error_ = false;
};

}  // namespace rtu
