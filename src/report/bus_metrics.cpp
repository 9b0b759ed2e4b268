#include "report/bus_metrics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <string_view>
#include <utility>

#include "core/function_codes.hpp"
#include "report/prometheus_text.hpp"

namespace rtu {
namespace {

constexpr double kSecondsPerNano = 1e-9;

// A function as a label: the public name in snake case ("read_holding_registers"); other
// codes by number ("fc_101"), so two codes never share a series.
std::string function_label(std::uint8_t function) {
  if (!is_public_function(function)) return fmt::format("fc_{}", function);
  std::string label;
  for (const char c : function_name(function)) {
    label += c == ' ' || c == '/' || c == '-'
                 ? '_'
                 : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return label;
}

std::string_view model_label(const TrafficStats& stats, std::uint8_t slave) {
  const std::string_view model = stats.device_model(slave);
  return model.empty() ? std::string_view("unknown") : model;
}

// Writes one family after another; each helper declares its family, then its samples.
class Families {
 public:
  Families(const std::string& bus, const TrafficStats& stats) : bus_(bus), stats_(stats) {}

  template <typename Fn>
  void per_slave(Fn&& fn) const {
    for (unsigned a = 0; a < 256; ++a) {
      const SlaveStats* s = stats_.slave(static_cast<std::uint8_t>(a));
      if (s != nullptr) fn(static_cast<std::uint8_t>(a), *s, fmt::format("{}", a));
    }
  }

  ExpositionWriter out;
  const std::string& bus_;
  const TrafficStats& stats_;
};

void write_bus_totals(Families& f) {
  const Totals& t = f.stats_.totals();
  ExpositionWriter& out = f.out;
  const std::string_view bus = f.bus_;
  out.family("rtuscope_frames_total", MetricType::kCounter, "Modbus RTU frames seen on the bus.");
  out.sample("rtuscope_frames_total", {{"bus", bus}}, static_cast<double>(t.frames));
  out.family("rtuscope_bytes_total", MetricType::kCounter,
             "Bytes seen on the bus, noise included.");
  out.sample("rtuscope_bytes_total", {{"bus", bus}}, static_cast<double>(t.bytes));
  out.family("rtuscope_noise_bytes_total", MetricType::kCounter,
             "Bytes that formed no Modbus frame.");
  out.sample("rtuscope_noise_bytes_total", {{"bus", bus}}, static_cast<double>(t.noise_bytes));
  out.family("rtuscope_line_errors_total", MetricType::kCounter,
             "Records with a parity error, framing error, break or receiver overrun, by kind.");
  const std::pair<std::string_view, std::uint64_t> kinds[] = {{"parity", t.parity_errors},
                                                              {"framing", t.framing_errors},
                                                              {"break", t.breaks},
                                                              {"overrun", t.overruns}};
  for (const auto& [kind, n] : kinds) {
    out.sample("rtuscope_line_errors_total", {{"bus", bus}, {"kind", kind}},
               static_cast<double>(n));
  }
  out.family("rtuscope_broadcasts_total", MetricType::kCounter,
             "Broadcast requests (slave 0), which expect no response.");
  out.sample("rtuscope_broadcasts_total", {{"bus", bus}}, static_cast<double>(t.broadcasts));
}

void write_slave_counters(
    Families& f, const std::array<std::map<std::uint8_t, std::uint64_t>*, 256>& responses) {
  ExpositionWriter& out = f.out;
  const std::string_view bus = f.bus_;
  out.family("rtuscope_requests_total", MetricType::kCounter,
             "Requests the master sent to a slave, by function.");
  f.per_slave([&](std::uint8_t a, const SlaveStats& s, const std::string& slave) {
    for (const auto& [function, n] : s.functions) {
      const std::string name = function_label(function);
      out.sample(
          "rtuscope_requests_total",
          {{"bus", bus}, {"slave", slave}, {"model", model_label(f.stats_, a)}, {"function", name}},
          static_cast<double>(n));
    }
  });
  out.family("rtuscope_responses_total", MetricType::kCounter,
             "Responses from a slave (exception responses included), by function.");
  f.per_slave([&](std::uint8_t a, const SlaveStats&, const std::string& slave) {
    if (responses[a] == nullptr) return;
    for (const auto& [function, n] : *responses[a]) {
      const std::string name = function_label(function);
      out.sample(
          "rtuscope_responses_total",
          {{"bus", bus}, {"slave", slave}, {"model", model_label(f.stats_, a)}, {"function", name}},
          static_cast<double>(n));
    }
  });
  out.family("rtuscope_exceptions_total", MetricType::kCounter,
             "Exception responses from a slave, by exception code.");
  f.per_slave([&](std::uint8_t a, const SlaveStats& s, const std::string& slave) {
    for (const auto& [code, n] : s.exception_codes) {
      const std::string code_text = fmt::format("{}", code);
      out.sample("rtuscope_exceptions_total",
                 {{"bus", bus},
                  {"slave", slave},
                  {"model", model_label(f.stats_, a)},
                  {"code", code_text}},
                 static_cast<double>(n));
    }
  });
  out.family("rtuscope_timeouts_total", MetricType::kCounter,
             "Intact requests to a slave that got no response within the response timeout.");
  f.per_slave([&](std::uint8_t a, const SlaveStats& s, const std::string& slave) {
    out.sample("rtuscope_timeouts_total",
               {{"bus", bus}, {"slave", slave}, {"model", model_label(f.stats_, a)}},
               static_cast<double>(s.timeouts));
  });
  out.family("rtuscope_crc_errors_total", MetricType::kCounter,
             "Frames to or from a slave (by their address byte) that failed the CRC check.");
  f.per_slave([&](std::uint8_t, const SlaveStats& s, const std::string& slave) {
    out.sample("rtuscope_crc_errors_total", {{"bus", bus}, {"slave", slave}},
               static_cast<double>(s.issues[IssueId::kCrc]));
  });
}

// Per slave, and for the records no slave owns (noise, broadcasts) as slave="none".
void write_issues(Families& f) {
  ExpositionWriter& out = f.out;
  const std::string_view bus = f.bus_;
  out.family("rtuscope_issues_total", MetricType::kCounter,
             "Records carrying an issue of the catalogue, by issue key.");
  IssueCounts unowned = f.stats_.totals().issues;
  std::array<std::uint64_t, static_cast<unsigned>(IssueId::kCount)> owned{};
  f.per_slave([&](std::uint8_t, const SlaveStats& s, const std::string& slave) {
    s.issues.for_each([&](IssueId id, std::uint64_t n) {
      owned[static_cast<unsigned>(id)] += n;
      out.sample("rtuscope_issues_total",
                 {{"bus", bus}, {"slave", slave}, {"issue", issue_info(id).key}},
                 static_cast<double>(n));
    });
  });
  unowned.for_each([&](IssueId id, std::uint64_t n) {
    const std::uint64_t rest = n - owned[static_cast<unsigned>(id)];
    if (rest == 0) return;
    out.sample("rtuscope_issues_total",
               {{"bus", bus}, {"slave", "none"}, {"issue", issue_info(id).key}},
               static_cast<double>(rest));
  });
}

void write_points(Families& f) {
  ExpositionWriter& out = f.out;
  out.family("rtuscope_point", MetricType::kGauge,
             "Latest value of a device point (named by the slave's map, else a raw register).");
  for (const auto& [key, series] : f.stats_.points()) {
    const std::string slave = fmt::format("{}", key.first);
    out.sample("rtuscope_point",
               {{"bus", f.bus_},
                {"slave", slave},
                {"model", model_label(f.stats_, key.first)},
                {"point", key.second},
                {"unit", series.unit}},
               series.last);
  }
}

void write_health(Families& f, const ToolHealth& h) {
  ExpositionWriter& out = f.out;
  const std::string_view bus = f.bus_;
  const auto one = [&](std::string_view name, MetricType type, std::string_view help,
                       double value) {
    out.family(name, type, help);
    if (!std::isnan(value)) out.sample(name, {{"bus", bus}}, value);
  };
  one("rtuscope_read_bytes_total", MetricType::kCounter, "Bytes read from the serial port(s).",
      static_cast<double>(h.read_bytes));
  one("rtuscope_seconds_since_last_byte", MetricType::kGauge,
      "Seconds since the last byte was read (absent before the first).", h.seconds_since_last_byte);
  one("rtuscope_port_disconnects_total", MetricType::kCounter,
      "Times a serial port stopped delivering (e.g. unplugged).",
      static_cast<double>(h.disconnects));
  one("rtuscope_port_reconnects_total", MetricType::kCounter,
      "Times a lost serial port was opened again.", static_cast<double>(h.reconnects));
  const double nan = NAN;
  one("rtuscope_capture_file_bytes_total", MetricType::kCounter,
      "Bytes written to capture files (-w), every file together.",
      h.recording ? static_cast<double>(h.capture_bytes) : nan);
  one("rtuscope_capture_rotations_total", MetricType::kCounter,
      "Capture files started after the first (--rotate).",
      h.recording && h.capture_files > 0 ? static_cast<double>(h.capture_files - 1) : nan);
  one("rtuscope_capture_reopens_total", MetricType::kCounter,
      "Times the capture file was re-opened on SIGHUP.",
      h.recording ? static_cast<double>(h.capture_reopens) : nan);
  out.family("rtuscope_table_overflows_total", MetricType::kCounter,
             "Entries a bounded table turned away (it stays bounded; the report is partial).");
  const std::pair<std::string_view, std::uint64_t> tables[] = {
      {"request_kinds", f.stats_.request_kinds_overflow()},
      {"points", f.stats_.points_overflow()},
      {"tracker_backlog", f.stats_.totals().issues[IssueId::kBacklogOverflow]}};
  for (const auto& [table, n] : tables) {
    out.sample("rtuscope_table_overflows_total", {{"bus", bus}, {"table", table}},
               static_cast<double>(n));
  }
}

}  // namespace

BusMetrics::BusMetrics(std::string bus, const TrafficStats& stats)
    : bus_(std::move(bus)), stats_(stats) {}

BusMetrics::~BusMetrics() = default;

void BusMetrics::on_capture(const CaptureInfo& info) {
  char_time_ = info.line.char_time();
}

void BusMetrics::on_record(Record& r) {
  if (first_t_ == kUnknownTime) first_t_ = r.t_start;
  // Busy time as the report counts it (size × character time), by the second it ended in.
  const std::int64_t second = r.t_end / kNanosPerSecond;
  BusySecond& slot = busy_[static_cast<std::size_t>(second) % busy_.size()];
  if (slot.second != second) slot = BusySecond{second, 0.0};
  slot.busy_ns += static_cast<double>(static_cast<Nanos>(r.size) * char_time_);

  if (r.kind != RecordKind::kFrame || r.role != Role::kResponse) return;
  auto& extras = slaves_[r.slave()];
  if (!extras) extras = std::make_unique<SlaveExtras>();
  ++extras->responses[static_cast<std::uint8_t>(r.function() & 0x7FU)];
  if (latency_unseen(r)) ++extras->latency_unseen;
  if (!counts_latency(r)) return;
  const double seconds = static_cast<double>(r.latency) * kSecondsPerNano;
  const auto* bound = std::lower_bound(kLatencyBounds.begin(), kLatencyBounds.end(), seconds);
  if (bound != kLatencyBounds.end()) {
    ++extras->latency_le[static_cast<std::size_t>(bound - kLatencyBounds.begin())];
  }
  ++extras->latency_count;
  extras->latency_sum += seconds;
}

double BusMetrics::utilisation(Nanos now) const {
  if (first_t_ == kUnknownTime || char_time_ == 0) return 0.0;
  const Nanos start = std::max(now - kUtilisationWindow, first_t_);
  if (now <= start) return 0.0;
  // Whole seconds inside the window; the oldest one may stick out by up to a second, which
  // the window's length below accounts for.
  const std::int64_t first_second = start / kNanosPerSecond;
  const std::int64_t last_second = now / kNanosPerSecond;
  double busy = 0.0;
  for (const BusySecond& slot : busy_) {
    if (slot.second >= first_second && slot.second <= last_second) busy += slot.busy_ns;
  }
  const Nanos window = now - std::max(first_second * kNanosPerSecond, first_t_);
  return std::clamp(busy / static_cast<double>(window), 0.0, 1.0);
}

std::string BusMetrics::exposition(Nanos now, const ToolHealth& health) const {
  Families f(bus_, stats_);
  write_bus_totals(f);
  std::array<std::map<std::uint8_t, std::uint64_t>*, 256> responses{};
  for (std::size_t a = 0; a < slaves_.size(); ++a) {
    if (slaves_[a]) responses[a] = &slaves_[a]->responses;
  }
  write_slave_counters(f, responses);
  write_issues(f);

  ExpositionWriter& out = f.out;
  const std::string_view bus = bus_;
  out.family("rtuscope_response_latency_seconds", MetricType::kHistogram,
             "Time from the end of a request to the start of its slave's intact response.");
  for (std::size_t a = 0; a < slaves_.size(); ++a) {
    if (!slaves_[a]) continue;
    const SlaveExtras& e = *slaves_[a];
    const std::string slave = fmt::format("{}", a);
    std::uint64_t cumulative = 0;
    for (std::size_t i = 0; i < kLatencyBounds.size(); ++i) {
      cumulative += e.latency_le[i];
      const std::string le = format_sample_value(kLatencyBounds[i]);
      out.sample("rtuscope_response_latency_seconds_bucket",
                 {{"bus", bus}, {"slave", slave}, {"le", le}}, static_cast<double>(cumulative));
    }
    out.sample("rtuscope_response_latency_seconds_bucket",
               {{"bus", bus}, {"slave", slave}, {"le", "+Inf"}},
               static_cast<double>(e.latency_count));
    out.sample("rtuscope_response_latency_seconds_sum", {{"bus", bus}, {"slave", slave}},
               e.latency_sum);
    out.sample("rtuscope_response_latency_seconds_count", {{"bus", bus}, {"slave", slave}},
               static_cast<double>(e.latency_count));
  }
  out.family("rtuscope_response_latency_unseen_total", MetricType::kCounter,
             "Intact responses whose latency the capture cannot show: they came in the read "
             "that ended their request (an adapter's batching), so the histogram leaves them out.");
  for (std::size_t a = 0; a < slaves_.size(); ++a) {
    if (!slaves_[a]) continue;
    out.sample("rtuscope_response_latency_unseen_total",
               {{"bus", bus}, {"slave", fmt::format("{}", a)}},
               static_cast<double>(slaves_[a]->latency_unseen));
  }
  out.family("rtuscope_bus_utilisation_ratio", MetricType::kGauge,
             "Share of the last 10 s the line carried bytes (bytes × character time).");
  out.sample("rtuscope_bus_utilisation_ratio", {{"bus", bus}}, utilisation(now));
  write_points(f);
  write_health(f, health);
  return out.text();
}

}  // namespace rtu
