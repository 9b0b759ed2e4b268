#pragma once
// Turns the records of a capture into bursts a TrafficPlayer can play: each record's bytes,
// sent by the slaves' side when it is a response, else by the master's, at its time
// relative to the first record.
#include <vector>

#include "framing/record.hpp"
#include "pipeline/traffic_player.hpp"

namespace rtu {

class BurstCollector final : public RecordSink {
 public:
  void on_record(Record& record) override;

  std::vector<Burst> bursts;

 private:
  Nanos first_ = kUnknownTime;
};

}  // namespace rtu
