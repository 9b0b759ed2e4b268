#include "pipeline/burst_collector.hpp"

namespace rtu {

void BurstCollector::on_record(Record& record) {
  if (first_ == kUnknownTime) first_ = record.t_start;
  bursts.push_back(Burst{record.t_start - first_,
                         record.role == Role::kResponse,
                         {record.bytes().begin(), record.bytes().end()}});
}

}  // namespace rtu
