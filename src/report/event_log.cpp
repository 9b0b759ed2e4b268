#include "report/event_log.hpp"

#include <fmt/format.h>

#include <array>
#include <type_traits>

#include "core/chunk.hpp"
#include "core/function_codes.hpp"
#include "core/json_writer.hpp"
#include "core/time_format.hpp"

namespace rtu {
namespace {

constexpr std::array kEventKeys = {
#define RTU_EVENT(id, key, summary) std::string_view(key),
#include "report/events.def"
#undef RTU_EVENT
};

constexpr std::array kFieldKeys = {
#define RTU_EVENT_FIELD(id, key, summary) std::string_view(key),
#include "report/events.def"
#undef RTU_EVENT_FIELD
};

void write_value(JsonWriter& j, const EventValue& value) {
  std::visit(
      [&j](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          j.null();
        } else if constexpr (std::is_same_v<T, double>) {
          j.value_double(v);
        } else if constexpr (std::is_same_v<T, std::span<const std::string_view>>) {
          j.begin_array();
          for (const auto text : v) j.value(text);
          j.end_array();
        } else {
          j.value(v);
        }
      },
      value);
}

EventValue model_of(const dissect::DeviceTable* devices, std::uint8_t slave) {
  if (devices == nullptr || devices->model(slave).empty()) return std::monostate{};
  return devices->model(slave);
}

}  // namespace

std::string_view event_key(EventKind kind) {
  return kEventKeys.at(static_cast<std::size_t>(kind));
}

std::string_view event_field_key(EventField field) {
  return kFieldKeys.at(static_cast<std::size_t>(field));
}

EventLog::EventLog(OutputStream& out, std::string bus) : out_(out), bus_(std::move(bus)) {}

void EventLog::emit(EventKind kind, Nanos t,
                    std::initializer_list<std::pair<EventField, EventValue>> fields) {
  buffer_.clear();
  fmt::memory_buffer time;
  append_utc_date(time, t);
  time.push_back('T');
  append_utc_time_of_day(time, t, 6);
  time.push_back('Z');
  JsonWriter j(buffer_);
  j.begin_object();
  j.field(event_field_key(EventField::kTime), std::string_view(time.data(), time.size()));
  j.field(event_field_key(EventField::kBus), std::string_view(bus_));
  j.field(event_field_key(EventField::kEvent), event_key(kind));
  for (const auto& [field, value] : fields) {
    j.key(event_field_key(field));
    write_value(j, value);
  }
  j.end_object();
  buffer_.push_back('\n');
  out_.write(buffer_);
  out_.flush();
  ++written_;
}

RecordEvents::RecordEvents(EventLog& log, const dissect::DeviceTable* devices)
    : log_(log), devices_(devices) {}

void RecordEvents::on_record(Record& r) {
  if (r.line_errors != 0) {
    std::array<std::string_view, 4> kinds;
    std::size_t n = 0;
    if ((r.line_errors & kParityError) != 0) kinds[n++] = "parity";
    if ((r.line_errors & kFramingError) != 0) kinds[n++] = "framing";
    if ((r.line_errors & kBreak) != 0) kinds[n++] = "break";
    if ((r.line_errors & kOverrun) != 0) kinds[n++] = "overrun";
    const EventValue slave = r.kind == RecordKind::kFrame ? EventValue(std::uint64_t{r.slave()})
                                                          : EventValue(std::monostate{});
    log_.emit(EventKind::kLineError, r.t_start,
              {{EventField::kKinds, std::span<const std::string_view>(kinds.data(), n)},
               {EventField::kSlave, slave}});
  }
  if (r.kind != RecordKind::kFrame) return;
  if (r.role == Role::kRequest && r.issues.has(IssueId::kTimeout) && !is_damaged(r) &&
      r.slave() != 0) {
    log_.emit(EventKind::kTimeout, r.t_end,
              {{EventField::kSlave, std::uint64_t{r.slave()}},
               {EventField::kModel, model_of(devices_, r.slave())},
               {EventField::kFunction, std::uint64_t{r.function()}}});
  }
  if (r.role == Role::kResponse && r.is_exception() && r.size >= 3) {
    const std::uint8_t code = r.bytes()[2];
    const std::string_view name =
        devices_ != nullptr && !devices_->exception_name(r.slave(), code).empty()
            ? devices_->exception_name(r.slave(), code)
            : exception_name(code);
    log_.emit(EventKind::kException, r.t_end,
              {{EventField::kSlave, std::uint64_t{r.slave()}},
               {EventField::kModel, model_of(devices_, r.slave())},
               {EventField::kFunction, std::uint64_t{r.function() & 0x7FU}},
               {EventField::kCode, std::uint64_t{code}},
               {EventField::kName, name}});
  }
}

void FindingEvents::check(const TrafficStats& stats, Nanos now) {
  for (const Finding& f : find_problems(stats)) {
    const int slave = f.slave ? int{*f.slave} : -1;
    if (!seen_.emplace(f.key, slave).second) continue;
    log_.emit(EventKind::kFinding, now,
              {{EventField::kKey, std::string_view(f.key)},
               {EventField::kSeverity, severity_name(f.severity)},
               {EventField::kSlave,
                f.slave ? EventValue(std::uint64_t{*f.slave}) : EventValue(std::monostate{})},
               {EventField::kSummary, std::string_view(f.summary)}});
  }
}

std::string HealthSummary::write(const TrafficStats& stats, Nanos now) {
  const Totals& t = stats.totals();
  const Totals& p = previous_;
  const Nanos since = previous_t_ != kUnknownTime ? previous_t_
                      : t.first_t != kUnknownTime ? t.first_t
                                                  : now;
  const double period_s = std::max(0.0, to_seconds(now - since));
  const double utilisation =
      period_s > 0 ? std::min(1.0, (t.busy_ns - p.busy_ns) / (period_s * 1e9)) : 0.0;
  std::uint64_t slaves = 0;
  for (unsigned a = 0; a < 256; ++a)
    slaves += stats.slave(static_cast<std::uint8_t>(a)) != nullptr ? 1U : 0U;
  const std::uint64_t crc = t.issues[IssueId::kCrc] - p.issues[IssueId::kCrc];
  const std::string text = fmt::format(
      "rtuscope summary of the last {:.0f} s: {} frames, {} requests, {} responses, {} "
      "timeouts, {} exceptions, {} CRC errors, {} line errors, {} noise bytes, {:.1f}% busy, "
      "{} slaves seen",
      period_s, t.frames - p.frames, t.requests - p.requests, t.responses - p.responses,
      t.timeouts - p.timeouts, t.exceptions - p.exceptions, crc,
      t.line_error_records - p.line_error_records, t.noise_bytes - p.noise_bytes, utilisation * 100,
      slaves);
  if (log_ != nullptr) {
    log_->emit(EventKind::kSummary, now,
               {{EventField::kPeriodS, period_s},
                {EventField::kFrames, t.frames - p.frames},
                {EventField::kRequests, t.requests - p.requests},
                {EventField::kResponses, t.responses - p.responses},
                {EventField::kTimeouts, t.timeouts - p.timeouts},
                {EventField::kExceptions, t.exceptions - p.exceptions},
                {EventField::kCrcErrors, crc},
                {EventField::kLineErrors, t.line_error_records - p.line_error_records},
                {EventField::kNoiseBytes, t.noise_bytes - p.noise_bytes},
                {EventField::kUtilisation, utilisation},
                {EventField::kSlaves, slaves},
                {EventField::kSummary, std::string_view(text)}});
  }
  previous_ = t;
  previous_t_ = now;
  return text;
}

}  // namespace rtu
