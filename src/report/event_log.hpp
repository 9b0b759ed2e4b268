#pragma once
// `--events FILE|-`: one JSON object per line for log shippers, each with the wall-clock
// time, the bus name and the event key first. Event keys and the keys of their fields come
// from events.def only, so a consumer's filter never meets a key spelt two ways.
//
// RecordEvents turns records into events as they pass (timeouts, exceptions, line errors);
// the live session adds the rest (findings, ports lost and back, rotations, summaries).
#include <cstdint>
#include <initializer_list>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

#include "core/output_stream.hpp"
#include "dissect/device_table.hpp"
#include "framing/record.hpp"
#include "report/findings.hpp"
#include "report/traffic_stats.hpp"

namespace rtu {

enum class EventKind : std::uint8_t {
#define RTU_EVENT(id, key, summary) id,
#include "report/events.def"
#undef RTU_EVENT
};

enum class EventField : std::uint8_t {
#define RTU_EVENT_FIELD(id, key, summary) id,
#include "report/events.def"
#undef RTU_EVENT_FIELD
};

std::string_view event_key(EventKind kind);
std::string_view event_field_key(EventField field);

// A field's value: a number, a text, a list of texts, or null (std::monostate). Texts are
// not owned: they need to live only until emit() returns.
using EventValue = std::variant<std::monostate, std::int64_t, std::uint64_t, double,
                                std::string_view, std::span<const std::string_view>>;

class EventLog {
 public:
  // `out` (not owned) receives the lines; each line is flushed as written, so a shipper
  // following the file sees every event at once.
  EventLog(OutputStream& out, std::string bus);

  // Writes one event at capture time `t` (ns since 1970) with `fields` after the common ones.
  void emit(EventKind kind, Nanos t,
            std::initializer_list<std::pair<EventField, EventValue>> fields = {});
  [[nodiscard]] std::uint64_t written() const { return written_; }

 private:
  OutputStream& out_;
  std::string bus_;
  fmt::memory_buffer buffer_;
  std::uint64_t written_ = 0;
};

// Timeouts (of intact requests, as the report counts them), exception responses and line
// errors, as the records carrying them pass.
class RecordEvents final : public RecordSink {
 public:
  // `devices` (not owned, may be null) names the slaves' models.
  RecordEvents(EventLog& log, const dissect::DeviceTable* devices);
  void on_record(Record& record) override;

 private:
  EventLog& log_;
  const dissect::DeviceTable* devices_;
};

// Findings the first time they show: call check() now and then; each finding (key and
// slave) is written once per run.
class FindingEvents {
 public:
  explicit FindingEvents(EventLog& log) : log_(log) {}
  void check(const TrafficStats& stats, Nanos now);

 private:
  EventLog& log_;
  std::set<std::pair<std::string, int>> seen_;
};

// The health summary of the period since the previous one: counts from the report's
// statistics. Returns the one-line text it also put in the event (for a capture comment).
class HealthSummary {
 public:
  explicit HealthSummary(EventLog* log) : log_(log) {}
  std::string write(const TrafficStats& stats, Nanos now);

 private:
  EventLog* log_;  // may be null: the text alone
  Totals previous_;
  Nanos previous_t_ = kUnknownTime;
};

}  // namespace rtu
