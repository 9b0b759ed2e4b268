#pragma once
// Findings: a short ranked list of what is wrong on the bus and what probably causes it,
// computed from TrafficStats. Each finding has a stable key (public: JSON, HTML, scripts),
// a severity, the numbers behind it, and one sentence of likely cause. A finding is made
// only where the data supports it: timing findings need timestamps fine enough to show the
// silences in question, and each has a minimum count so that one stray frame claims nothing.
//
// Keys (never renamed; thresholds in findings.cpp next to each rule):
//   crc_errors_one_slave          CRC errors concentrated on one slave's frames
//   crc_errors_long_frames        CRC error rate grows with frame length
//   crc_errors_spread             CRC errors on several slaves and lengths alike
//   turnaround_glitches           lone 0x00/0xFF bytes after a turnaround that the framer
//                                 did not flag (never the same records as turnaround_glitch)
//   turnaround_glitch             lone bytes the framer flagged right after one sender's
//                                 frames: that sender's RS-485 driver, or the bus floating
//                                 when they carry framing errors/breaks (one per sender)
//   damaged_requests              requests the wire damaged went unanswered (not timeouts)
//   pauses_in_responses           silences > t1.5 inside one slave's responses
//   responses_after_next_request  a slave's answers arrive after the master moved on
//   two_masters                   requests while a slave's answer is due, at varying times
//                                 (a master that gave up would wait the same timeout)
//   unsolicited_responses         responses with no request (not explained as late answers)
//   line_errors_one_device        parity/framing errors where one slave's answer is due
//   line_errors                   parity/framing errors with valid frames in between
//                                 (both leave out line errors on turnaround glitches)
//   slave_not_responding          a slave answers (almost) none of its requests
//   slave_timeouts                a slave misses some of its requests
//   timeout_fit                   which master timeout would lose which share of answers
//   exceptions_for_request        a request kind is answered with exceptions
//   master_polls_too_fast         requests start < t3.5 after the previous frame
//   responses_too_soon            a slave answers < t3.5 after the request
//   request_echo                  requests seen twice in a row, the copy within t3.5: an
//                                 adapter's echo (the first copies read as timeouts)
//   bus_busy                      the line is nearly always carrying bytes
//   noise                         bytes that form no frame, beyond both turnaround glitches
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/issue.hpp"
#include "report/traffic_stats.hpp"

namespace rtu {

// One number behind a finding. `name` is a stable snake_case key.
struct Evidence {
  std::string name;
  double value = 0.0;
  std::string unit;  // "", "%", "ms", "bytes"
};

struct Finding {
  std::string key;
  Severity severity = Severity::kInfo;
  std::optional<std::uint8_t> slave;  // the slave it is about, if one
  std::string summary;                // what the data shows, with its numbers
  std::string cause;                  // the likely cause, one sentence
  std::vector<Evidence> evidence;
  double weight = 0.0;  // ranks findings of equal severity: share of traffic affected
};

// Ranked: errors first, then warnings, then information; within a severity, larger weight
// first, then key and slave (so the order is stable).
std::vector<Finding> find_problems(const TrafficStats& stats);

}  // namespace rtu
