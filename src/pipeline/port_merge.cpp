#include "pipeline/port_merge.hpp"

#include <algorithm>

namespace rtu {

PortMerge::PortMerge(RecordSink& out, const std::vector<std::unique_ptr<Framer>>& framers)
    : out_(out), framers_(framers), held_(1) {}

void PortMerge::set_port_count(std::size_t count) {
  if (count > held_.size()) held_.resize(count);
}

void PortMerge::pass(Record& record) {
  record.seq = next_seq_++;
  out_.on_record(record);
}

void PortMerge::on_record(std::size_t port, Record& record) {
  if (held_.size() == 1) {
    pass(record);
    return;
  }
  // Held until the next read is in (drain): records of several ports leave only at reads,
  // never at a live run's idle times, so live and replay merge them the same way.
  held_.at(port).push_back(record);
}

std::size_t PortMerge::earliest_port() const {
  std::size_t best = held_.size();
  for (std::size_t p = 0; p < held_.size(); ++p) {
    if (held_[p].empty()) continue;
    if (best == held_.size() || held_[p].front().t_start < held_[best].front().t_start) best = p;
  }
  return best;
}

void PortMerge::drain_held() {
  for (;;) {
    // The earliest record held on any port...
    const std::size_t best = earliest_port();
    if (best == held_.size()) return;
    // ...leaves once no port with nothing held could still emit an earlier one.
    const Nanos t = held_[best].front().t_start;
    for (std::size_t p = 0; p < held_.size(); ++p) {
      if (p == best || !held_[p].empty()) continue;
      const Nanos pending = framers_[p]->oldest_pending_start();
      if (pending != kUnknownTime && pending < t) return;
    }
    pass(held_[best].front());
    held_[best].pop_front();
  }
}

void PortMerge::flush() {
  for (;;) {
    const std::size_t best = earliest_port();
    if (best == held_.size()) return;
    pass(held_[best].front());
    held_[best].pop_front();
  }
}

Nanos PortMerge::oldest_held_or_pending_start() const {
  Nanos oldest = kUnknownTime;
  const auto take = [&oldest](Nanos t) {
    if (t != kUnknownTime && (oldest == kUnknownTime || t < oldest)) oldest = t;
  };
  for (std::size_t p = 0; p < held_.size(); ++p) {
    if (!held_[p].empty()) take(held_[p].front().t_start);
    take(framers_[p]->oldest_pending_start());
  }
  return oldest;
}

}  // namespace rtu
