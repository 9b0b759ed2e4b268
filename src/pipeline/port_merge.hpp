#pragma once
// Merges the records of one framer per receiving port into one time-ordered stream for
// the transaction tracker.
//
// With two ports (the two directions of an RS-232/RS-422 link, or two adapters on one
// bus) each port's bytes are framed on their own: bytes of a request and of a response
// that overlap in time must never be interleaved into one frame. A record is passed on
// once no other port still holds bytes that could start earlier, when a read has been fed
// (drain): a read's first byte is placed by counting back from its arrival, so it may
// still come before a record that an idle moment could have released, and a live run and
// its replay must release in the same order. With one port records pass straight through.
//
// Records are numbered here (Record::seq), in the order they leave.
#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include "framing/framer.hpp"
#include "framing/record.hpp"

namespace rtu {

class PortMerge {
 public:
  // `framers[port]` is port's framer: what it still holds could precede a held record.
  // Asked directly (inline, at every read), not through a callback.
  PortMerge(RecordSink& out, const std::vector<std::unique_ptr<Framer>>& framers);

  // Called by port `port`'s framer for each record it emits.
  void on_record(std::size_t port, Record& record);
  // Ports are 0..count-1; more ports mean merging.
  void set_port_count(std::size_t count);
  // Passes on the held records that no port can precede any more; called once a read was
  // fed to its port's framer.
  // Both are asked at every read; with one port (nearly every capture) records pass at once
  // and none is held, which is decided here, inline.
  void drain() {
    if (held_.size() > 1) drain_held();
  }
  // Passes on every held record (end of input).
  void flush();
  // Start of the oldest record held or still to come from a framer; kUnknownTime if none.
  [[nodiscard]] Nanos oldest_pending_start() const {
    return held_.size() == 1 ? framers_[0]->oldest_pending_start() : oldest_held_or_pending_start();
  }

 private:
  void drain_held();
  [[nodiscard]] Nanos oldest_held_or_pending_start() const;
  // The port whose first held record starts earliest; held_.size() when none is held.
  [[nodiscard]] std::size_t earliest_port() const;
  void pass(Record& record);

  RecordSink& out_;
  const std::vector<std::unique_ptr<Framer>>& framers_;
  std::vector<std::deque<Record>> held_;
  std::uint64_t next_seq_ = 0;
};

// The RecordSink a port's framer writes to.
class PortOutput final : public RecordSink {
 public:
  PortOutput(PortMerge& merge, std::size_t port) : merge_(merge), port_(port) {}
  void on_record(Record& record) override { merge_.on_record(port_, record); }

 private:
  PortMerge& merge_;
  std::size_t port_;
};

}  // namespace rtu
