#pragma once
// Pairs requests with responses on a single-master bus and decides each frame's role.
//
// Modbus RTU has one master and at most one open request: a response carries the same
// slave address and function (or its exception). Echo functions (05, 06, 08, 22) have
// requests and responses of the same shape, so their role comes from order. A new
// request before the response closes the old one as a timeout; a response with no open
// request is unsolicited; a response from another slave or function is paired and
// flagged. Broadcasts (slave 0) expect no response.
//
// Records leave in time order. A request is held back until its fate is known (answer,
// timeout), together with the records that arrived meanwhile; that backlog is bounded,
// and overflowing it releases the request without a verdict (`backlog_overflow`) rather
// than growing.
#include <array>
#include <cstdint>

#include "framing/record.hpp"
#include "modbus/pdu.hpp"
#include "pairing/pairing_input.hpp"

namespace rtu {

struct TrackerConfig {
  Nanos response_timeout = 1000 * kNanosPerMilli;
};

class TransactionTracker final : public PairingInput {
 public:
  TransactionTracker(const TrackerConfig& config, RecordSink& out);
  // Not copied: open_pdu_ views the tracker's own open_.
  TransactionTracker(const TransactionTracker&) = delete;
  TransactionTracker& operator=(const TransactionTracker&) = delete;

  void on_capture(const CaptureInfo& info) override { out_.on_capture(info); }
  void on_record(Record& record) override;
  void on_finish() override;
  void on_break() override;
  // No record can start before `now`: a request whose response timeout ran out before it
  // is released as timed out. An answer that still comes is flagged `late`, with no txn
  // (its request has already gone out unmatched); one that comes after the timeout with
  // no advance() between is treated the same, so the verdict never depends on when
  // advance() was called.
  void advance(Nanos now) override;
  // A request waits for its answer and advance() may still time it out.
  [[nodiscard]] bool awaits_timeout() const { return awaiting_answer() && !released_; }
  // The first moment advance() would time that request out; kUnknownTime when none waits.
  [[nodiscard]] Nanos timeout_at() const {
    return awaits_timeout() ? open_.t_end + config_.response_timeout + 1 : kUnknownTime;
  }

 private:
  static constexpr std::size_t kMaxHeld = 64;

  Role decide_role(const Record& frame) const;
  void handle_request(Record& frame);
  void handle_response(Record& frame);
  void close_open(bool timed_out);
  // The open request's response timeout ran out: it leaves now, with what it held back.
  // The capture ends (or breaks): the open request leaves with what it held, timed out if
  // the last record came after its timeout ran out, else without a verdict.
  void end_exchange();
  void release_timed_out();
  void emit(Record& record);
  void release_held();
  [[nodiscard]] bool awaiting_answer() const { return has_open_ && !answered_; }

  TrackerConfig config_;
  RecordSink& out_;

  Record open_;  // the newest request that expects an answer
  // open_ decoded, where its CRC holds (views into open_); open_.pdu and held_[0].pdu point
  // to it then.
  FramePdu open_pdu_;
  bool has_open_ = false;
  bool answered_ = false;
  bool released_ = false;                // the open request went out as timed out (advance)
  std::array<Record, kMaxHeld> held_{};  // held_[0] is the open request while held
  std::size_t held_count_ = 0;
  std::int64_t next_txn_ = 0;
  Nanos last_time_ = kUnknownTime;
};

}  // namespace rtu
