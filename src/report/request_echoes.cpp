#include "report/request_echoes.hpp"

#include <algorithm>
#include <cstring>

namespace rtu {

void RequestEchoes::on_frame(const Record& frame, bool is_request) {
  const bool intact = frame.crc_ok && is_request;
  if (intact && last_size_ == frame.size &&
      std::memcmp(last_.data(), frame.storage.data(), frame.size) == 0 &&
      frame.t_start - last_end_ <= window_) {
    ++echoes_;
    if (last_timed_out_) ++timeouts_;
    longest_gap_ = std::max(longest_gap_, std::max<Nanos>(0, frame.t_start - last_end_));
    last_size_ = 0;  // a third copy is not a second echo of the first
    return;
  }
  if (!intact) {
    last_size_ = 0;
    return;
  }
  std::memcpy(last_.data(), frame.storage.data(), frame.size);
  last_size_ = frame.size;
  last_end_ = frame.t_end;
  last_timed_out_ = frame.issues.has(IssueId::kTimeout);
}

}  // namespace rtu
