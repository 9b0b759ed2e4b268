#include "pairing/transaction_tracker.hpp"

#include "core/function_codes.hpp"
#include "modbus/pdu.hpp"

namespace rtu {
namespace {

// Requests that get no response by design (MODBUS over Serial Line §2.1; FC08 sub 04,
// Force Listen Only Mode, V1.1b3 §6.8.1).
bool expects_no_response(const Record& request) {
  if (request.slave() == 0) return true;
  const auto b = request.bytes();
  return request.function() == fc::kDiagnostics && b.size() >= 4 && b[2] == 0 && b[3] == 4;
}

}  // namespace

TransactionTracker::TransactionTracker(const TrackerConfig& config, RecordSink& out)
    : config_(config), out_(out) {}

Role TransactionTracker::decide_role(const Record& frame) const {
  if (frame.is_exception()) return Role::kResponse;
  const bool fits_request = (frame.shape_fit & kFitsRequest) != 0;
  const bool fits_response = (frame.shape_fit & kFitsResponse) != 0;
  const bool awaited =
      awaiting_answer() && frame.slave() == open_.slave() && frame.function() == open_.function();
  if (fits_request && !fits_response) return Role::kRequest;
  if (fits_response && !fits_request) return Role::kResponse;
  if (fits_request && fits_response) return awaited ? Role::kResponse : Role::kRequest;
  // Fits no length rule: a function with no rule (vendor codes), a frame whose counts lie,
  // or a damaged one. Order decides where the CRC vouches for the frame: a response is
  // what the open request awaits, anything else starts a new exchange.
  if (awaited) return Role::kResponse;
  return frame.crc_ok ? Role::kRequest : Role::kUnknown;
}

void TransactionTracker::on_record(Record& record) {
  last_time_ = record.t_end;
  // Records come in time order: none still to come starts before this one, which is what
  // advance() is told. A request whose timeout ran out before it is released as timed out
  // before the record is held behind it, however few idle moments came between (a replay
  // has none): otherwise noise after the timeout could fill the backlog in a replay where
  // a live run's idle moment had released the request.
  advance(record.t_start);
  if (record.kind == RecordKind::kNoise) {
    emit(record);
    return;
  }
  record.role = decide_role(record);
  switch (record.role) {
    case Role::kRequest: handle_request(record); break;
    case Role::kResponse: handle_response(record); break;
    case Role::kUnknown:
      if (record.crc_ok) record.issues.merge(check_pdu(decode_pdu(record, Role::kUnknown)));
      emit(record);
      break;
  }
}

void TransactionTracker::handle_request(Record& frame) {
  if (has_open_) close_open(!answered_);
  // Content checks only where the CRC vouches for the content (here and below).
  if (expects_no_response(frame)) {
    if (frame.crc_ok) frame.issues.merge(check_pdu(decode_pdu(frame, Role::kRequest)));
    frame.txn = next_txn_++;
    emit(frame);
    return;
  }
  // Only the bytes in use: a whole Record is 360 bytes, most of them unused storage.
  open_.copy_in_use(frame);
  if (open_.crc_ok) {
    // Decoded from the tracker's own copy, which stays as it is while the request is open:
    // its answer is checked against it without decoding it again.
    open_pdu_.pdu = decode_pdu(open_, Role::kRequest);
    const IssueSet found = check_pdu(open_pdu_.pdu);
    open_.issues.merge(found);
    frame.issues.merge(found);
  }
  // The stages after this one take the decoding with the request, and with its response (as
  // its request's); both stay until open_ takes the next request, after held_[0] went out.
  open_.pdu = open_.crc_ok ? &open_pdu_ : nullptr;
  has_open_ = true;
  answered_ = false;
  released_ = false;
  held_[0].copy_in_use(frame);
  held_[0].pdu = open_.pdu;
  held_count_ = 1;
}

void TransactionTracker::handle_response(Record& frame) {
  if (!awaiting_answer()) {
    frame.issues.add(IssueId::kUnsolicited);
    if (frame.crc_ok) frame.issues.merge(check_pdu(decode_pdu(frame, Role::kResponse)));
    emit(frame);
    return;
  }
  // The open request's answer, possibly from the wrong slave or for the wrong function.
  if (frame.slave() != open_.slave()) frame.issues.add(IssueId::kWrongSlave);
  if ((frame.function() & 0x7FU) != open_.function()) frame.issues.add(IssueId::kWrongFunction);
  frame.latency = frame.t_start - open_.t_end;
  if (released_ || frame.latency > config_.response_timeout) {
    // After the response timeout: the request timed out and goes out unmatched, as it
    // does when an idle moment released it first (live), so a late answer has no txn
    // whenever it is seen.
    frame.issues.add(IssueId::kLate);
    if (!released_) release_timed_out();
  } else {
    open_.txn = next_txn_++;
    frame.txn = open_.txn;
    if (held_count_ > 0) {
      held_[0].txn = open_.txn;
      held_[0].issues = open_.issues;
      release_held();
    }
  }
  answered_ = true;
  frame.request = &open_;
  // Passed straight on, never held: the decoding may live on this stack.
  FramePdu decoded;
  if (frame.crc_ok) {
    decoded.pdu = decode_pdu(frame, Role::kResponse);
    frame.issues.merge(check_pdu(decoded.pdu));
    if (open_.crc_ok) {
      frame.issues.merge(check_response_fits(open_, open_pdu_.pdu, frame, decoded.pdu));
    }
    frame.pdu = &decoded;
  }
  out_.on_record(frame);
  frame.request = nullptr;
  frame.pdu = nullptr;
}

void TransactionTracker::close_open(bool timed_out) {
  if (timed_out) {
    open_.issues.add(IssueId::kTimeout);
    if (held_count_ > 0) held_[0].issues.add(IssueId::kTimeout);
  }
  release_held();
  has_open_ = false;
  answered_ = false;
}

void TransactionTracker::emit(Record& record) {
  if (held_count_ == 0) {
    out_.on_record(record);
    return;
  }
  if (held_count_ == kMaxHeld) {
    // Too much traffic while a request waits: release it without a verdict, and say so.
    held_[0].issues.add(IssueId::kBacklogOverflow);
    release_held();
    out_.on_record(record);
    return;
  }
  held_[held_count_++].copy_in_use(record);
}

void TransactionTracker::release_held() {
  for (std::size_t i = 0; i < held_count_; ++i) out_.on_record(held_[i]);
  held_count_ = 0;
}

void TransactionTracker::advance(Nanos now) {
  if (awaiting_answer() && !released_ && now - open_.t_end > config_.response_timeout) {
    release_timed_out();
  }
}

void TransactionTracker::release_timed_out() {
  open_.issues.add(IssueId::kTimeout);
  if (held_count_ > 0) held_[0].issues.add(IssueId::kTimeout);
  released_ = true;
  release_held();
}

void TransactionTracker::on_finish() {
  end_exchange();
  out_.on_finish();
}

void TransactionTracker::on_break() {
  end_exchange();
  has_open_ = false;  // what comes after the break answers nothing before it
  answered_ = false;
  released_ = false;
}

void TransactionTracker::end_exchange() {
  if (awaiting_answer() && last_time_ != kUnknownTime &&
      last_time_ - open_.t_end > config_.response_timeout) {
    close_open(true);
  } else {
    // The capture ended before the timeout ran out: no verdict.
    release_held();
  }
}

}  // namespace rtu
