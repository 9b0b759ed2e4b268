#include "report/jsonl_writer.hpp"

#include "core/function_codes.hpp"
#include "core/json_writer.hpp"
#include "core/time_format.hpp"
#include "dissect/device_stage.hpp"
#include "dissect/point_format.hpp"
#include "modbus/pdu.hpp"
#include "report/frame_text.hpp"
#include "report/timing_note.hpp"

namespace rtu {
namespace {

void write_time_key(JsonWriter& json, std::string_view key, Nanos t) {
  // Exact decimal seconds: written as a JSON number without going through a double.
  json.key(key);
  append_seconds(json.raw_value_buffer(), t);
}

void write_millis_key(JsonWriter& json, std::string_view key, Nanos t) {
  json.key(key);
  if (t == kUnknownTime) {
    json.null();
    return;
  }
  append_millis(json.raw_value_buffer(), t);
}

void write_issues(JsonWriter& json, const IssueSet& issues) {
  json.key("issues");
  json.begin_array();
  issues.for_each([&](IssueId id) { json.value(issue_info(id).key); });
  json.end_array();
}

}  // namespace

JsonlWriter::JsonlWriter(OutputStream& out) : out_(out) {}

void JsonlWriter::on_capture(const CaptureInfo& info) {
  buffer_.clear();
  JsonWriter json(buffer_);
  json.begin_object();
  json.field("kind", "capture");
  json.field("source", std::string_view(info.source));
  json.field("baud", static_cast<std::uint64_t>(info.line.baud));
  const char parity[2] = {parity_letter(info.line.parity), '\0'};
  json.field("parity", std::string_view(parity, 1));
  json.field("stop_bits", static_cast<unsigned>(info.line.stop_bits));
  write_millis_key(json, "char_time_ms", info.line.char_time());
  write_millis_key(json, "t1_5_ms", info.line.t1_5());
  write_millis_key(json, "t3_5_ms", info.line.t3_5());
  write_millis_key(json, "timing_resolution_ms", info.timing_resolution);
  json.field("per_byte_timing", info.per_byte_timing);
  write_millis_key(json, "response_timeout_ms", info.response_timeout);
  json.field("note", std::string_view(timing_note(info)));
  // Always present, empty when there is nothing to doubt: readers need not test for the key.
  json.key("warnings");
  json.begin_array();
  for (const std::string& w : info.warnings) json.value(std::string_view(w));
  json.end_array();
  json.end_object();
  buffer_.push_back('\n');
  out_.write(buffer_);
}

void JsonlWriter::on_record(Record& record) {
  const bool is_frame = record.kind == RecordKind::kFrame;
  // The device stage (when one runs) read the frame with the slave's map.
  const dissect::DeviceMap* map = record.device != nullptr ? record.device->map : nullptr;
  buffer_.clear();
  JsonWriter json(buffer_);
  json.begin_object();
  json.field("kind", is_frame ? "frame" : "noise");
  write_time_key(json, "t", record.t_start);
  write_time_key(json, "t_end", record.t_end);
  write_millis_key(json, "gap_ms", record.gap_before);
  json.key("hex");
  json.hex(record.bytes());
  if (is_frame) {
    json.field("slave", static_cast<unsigned>(record.slave()));
    json.field("fc", static_cast<unsigned>(record.function()));
    json.field("function", function_name(record.function()));
    json.field("crc_ok", record.crc_ok);
    json.field("role", role_name(record.role));
    json.key("txn");
    if (record.txn >= 0) {
      json.value(record.txn);
    } else {
      json.null();
    }
    if (record.role == Role::kResponse && record.latency != kUnknownTime) {
      write_millis_key(json, "latency_ms", record.latency);
    }
    if (record.is_exception() && record.size >= 3) {
      const std::uint8_t code = record.storage[2];
      std::string_view name = map != nullptr ? map->exception_name(code) : std::string_view{};
      if (name.empty()) name = exception_name(code);
      json.key("exception");
      json.begin_object();
      json.field("code", static_cast<unsigned>(code));
      json.field("name", name);
      json.end_object();
    }
  }
  write_issues(json, record.issues);
  if (is_frame) {
    // An exception's object is written above, with the device's own name when it has one.
    if (!(record.is_exception() && record.size >= 3)) {
      std::optional<DecodedPdu> scratch;
      write_pdu_json(json, decoding_of(record, record.role, scratch));
    }
    if (map != nullptr) {
      json.field("device", std::string_view(map->model));
      if (!record.device->decoded.points.empty()) {
        dissect::write_points_json(json, record.device->decoded);
      }
    }
  }
  json.end_object();
  buffer_.push_back('\n');
  out_.write(buffer_);
}

void JsonlWriter::on_finish() {
  out_.flush();
}

}  // namespace rtu
