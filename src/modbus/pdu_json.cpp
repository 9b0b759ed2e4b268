// write_pdu_json(): the decoded fields of a frame as keys of its JSON object.
//
// These keys are public and stable (tests, scripts and filters rely on them); add new
// ones, never rename. Numbers are plain integers (addresses too); `data`, `events` and
// `payload`-like bytes are lowercase hex strings; values are unsigned 16-bit integers.
//
// | PDU (FC, role)              | keys                                                       |
// |-----------------------------|------------------------------------------------------------|
// | any exception response      | exception {code, name}                                      |
// | raw (unknown FC, truncated) | data                                                        |
// | 01-04 request               | addr, qty                                                   |
// | 01/02 response              | addr, qty (only when the request is known), byte_count,     |
// |                             | coils [0/1] (trimmed to the request's qty)                  |
// | 03/04/23 response           | addr, qty (only when the request is known; FC23: its read   |
// |                             | part), byte_count, values [u16]                             |
// | 05 request / echo           | addr, value (raw u16), coil (true/false, null if invalid)  |
// | 06 request / echo           | addr, value                                                 |
// | 07/11/12/17 request         | (none)                                                      |
// | 07 response                 | status                                                      |
// | 08 either role              | sub_function, sub_function_name, data                       |
// | 11 response                 | status, event_count                                         |
// | 12 response                 | byte_count, status, event_count, message_count, events     |
// | 15 request                  | addr, qty, byte_count, coils [0/1]                          |
// | 16 request                  | addr, qty, byte_count, values [u16]                         |
// | 15/16 response              | addr, qty                                                   |
// | 17 response                 | byte_count, data                                            |
// | 20 request                  | byte_count, sub_requests [{ref_type, file, record, length}] |
// | 20 response                 | byte_count, records [{length, ref_type, values}]            |
// | 21 request / echo           | byte_count, records [{ref_type, file, record, length,       |
// |                             | values}]                                                    |
// | 22 request / echo           | addr, and_mask, or_mask                                     |
// | 23 request                  | read_addr, read_qty, write_addr, write_qty, byte_count,     |
// |                             | values                                                      |
// | 24 request                  | addr                                                        |
// | 24 response                 | byte_count, fifo_count, values                              |
// | 43/0E request               | mei, read_device_id_code, object_id                         |
// | 43/0E response              | mei, read_device_id_code, conformity, more_follows (bool),  |
// |                             | next_object_id, object_count, objects [{id, name, value}]   |
// |                             | (name null for reserved/private ids; value as text, bytes   |
// |                             | read as Latin-1)                                            |
// | 43 other MEI (0D ...)       | mei, data                                                   |
#include <array>

#include "core/function_codes.hpp"
#include "core/json_writer.hpp"
#include "modbus/pdu.hpp"
#include "modbus/pdu_names.hpp"

namespace rtu {
namespace {

void write_u16(JsonWriter& json, std::string_view key, std::uint16_t v) {
  json.field(key, unsigned{v});
}

void write_optional(JsonWriter& json, std::string_view key, std::optional<std::uint16_t> v) {
  if (v) write_u16(json, key, *v);
}

void write_words(JsonWriter& json, std::string_view key, WordView words) {
  json.key(key);
  json.u16_be_array(words.bytes());
}

void write_bits(JsonWriter& json, std::string_view key, BitView bits) {
  json.key(key);
  json.begin_array();
  for (std::size_t i = 0; i < bits.size(); ++i) json.value(bits[i] ? 1 : 0);
  json.end_array();
}

void write_hex(JsonWriter& json, std::string_view key, std::span<const std::uint8_t> bytes) {
  json.key(key);
  json.hex(bytes);
}

// Device id values are text in practice but may hold any byte: read them as Latin-1 so
// the JSON stays valid UTF-8 and nothing is lost.
void write_latin1(JsonWriter& json, std::span<const std::uint8_t> bytes) {
  std::array<char, 2 * kMaxAdu> text{};
  std::size_t n = 0;
  for (const std::uint8_t b : bytes) {
    if (n + 2 > text.size()) break;
    if (b < 0x80) {
      text[n++] = static_cast<char>(b);
    } else {
      text[n++] = static_cast<char>(0xC0U | (unsigned{b} >> 6U));
      text[n++] = static_cast<char>(0x80U | (unsigned{b} & 0x3FU));
    }
  }
  json.value(std::string_view(text.data(), n));
}

void write_fields(JsonWriter& json, const RawPdu& p) {
  write_hex(json, "data", p.data);
}

void write_fields(JsonWriter& json, const ExceptionResponse& p) {
  json.key("exception");
  json.begin_object();
  json.field("code", unsigned{p.code});
  json.field("name", exception_name(p.code));
  json.end_object();
}

void write_fields(JsonWriter& json, const ReadRequest& p) {
  write_u16(json, "addr", p.addr);
  write_u16(json, "qty", p.qty);
}

void write_fields(JsonWriter& json, const ReadBitsResponse& p) {
  write_optional(json, "addr", p.addr);
  write_optional(json, "qty", p.qty);
  json.field("byte_count", unsigned{p.byte_count});
  write_bits(json, "coils", p.bits);
}

void write_fields(JsonWriter& json, const ReadRegistersResponse& p) {
  write_optional(json, "addr", p.addr);
  write_optional(json, "qty", p.qty);
  json.field("byte_count", unsigned{p.byte_count});
  write_words(json, "values", p.values);
}

void write_fields(JsonWriter& json, const WriteSingle& p) {
  write_u16(json, "addr", p.addr);
  write_u16(json, "value", p.value);
  if (p.function == fc::kWriteSingleCoil) {
    json.key("coil");
    if (const auto on = p.coil()) {
      json.value(*on);
    } else {
      json.null();
    }
  }
}

void write_fields(JsonWriter& json, const WriteMultipleCoilsRequest& p) {
  write_u16(json, "addr", p.addr);
  write_u16(json, "qty", p.qty);
  json.field("byte_count", unsigned{p.byte_count});
  write_bits(json, "coils", p.coils);
}

void write_fields(JsonWriter& json, const WriteMultipleRegistersRequest& p) {
  write_u16(json, "addr", p.addr);
  write_u16(json, "qty", p.qty);
  json.field("byte_count", unsigned{p.byte_count});
  write_words(json, "values", p.values);
}

void write_fields(JsonWriter& json, const WriteMultipleResponse& p) {
  write_u16(json, "addr", p.addr);
  write_u16(json, "qty", p.qty);
}

void write_fields(JsonWriter& /*json*/, const NoDataRequest& /*p*/) {}

void write_fields(JsonWriter& json, const ExceptionStatusResponse& p) {
  json.field("status", unsigned{p.status});
}

void write_fields(JsonWriter& json, const DiagnosticsPdu& p) {
  write_u16(json, "sub_function", p.sub_function);
  json.field("sub_function_name", diagnostics_sub_function_name(p.sub_function));
  write_hex(json, "data", p.payload);
}

void write_fields(JsonWriter& json, const CommEventCounterResponse& p) {
  write_u16(json, "status", p.status);
  write_u16(json, "event_count", p.event_count);
}

void write_fields(JsonWriter& json, const CommEventLogResponse& p) {
  json.field("byte_count", unsigned{p.byte_count});
  write_u16(json, "status", p.status);
  write_u16(json, "event_count", p.event_count);
  write_u16(json, "message_count", p.message_count);
  write_hex(json, "events", p.events);
}

void write_fields(JsonWriter& json, const ServerIdResponse& p) {
  json.field("byte_count", unsigned{p.byte_count});
  write_hex(json, "data", p.payload);
}

void write_fields(JsonWriter& json, const FileRecordRequest& p) {
  json.field("byte_count", unsigned{p.byte_count});
  const bool write = p.records.layout() == FileRecordList::Layout::kWriteRequest;
  json.key(write ? "records" : "sub_requests");
  json.begin_array();
  for (const FileSubRecord& r : p.records) {
    json.begin_object();
    json.field("ref_type", unsigned{r.ref_type});
    write_u16(json, "file", r.file);
    write_u16(json, "record", r.record);
    write_u16(json, "length", r.record_length);
    if (write) write_words(json, "values", r.values);
    json.end_object();
  }
  json.end_array();
}

void write_fields(JsonWriter& json, const ReadFileRecordResponse& p) {
  json.field("byte_count", unsigned{p.byte_count});
  json.key("records");
  json.begin_array();
  for (const FileSubRecord& r : p.records) {
    json.begin_object();
    json.field("length", unsigned{r.resp_length});
    json.field("ref_type", unsigned{r.ref_type});
    write_words(json, "values", r.values);
    json.end_object();
  }
  json.end_array();
}

void write_fields(JsonWriter& json, const MaskWrite& p) {
  write_u16(json, "addr", p.addr);
  write_u16(json, "and_mask", p.and_mask);
  write_u16(json, "or_mask", p.or_mask);
}

void write_fields(JsonWriter& json, const ReadWriteMultipleRequest& p) {
  write_u16(json, "read_addr", p.read_addr);
  write_u16(json, "read_qty", p.read_qty);
  write_u16(json, "write_addr", p.write_addr);
  write_u16(json, "write_qty", p.write_qty);
  json.field("byte_count", unsigned{p.byte_count});
  write_words(json, "values", p.values);
}

void write_fields(JsonWriter& json, const FifoRequest& p) {
  write_u16(json, "addr", p.addr);
}

void write_fields(JsonWriter& json, const FifoResponse& p) {
  write_u16(json, "byte_count", p.byte_count);
  write_u16(json, "fifo_count", p.fifo_count);
  write_words(json, "values", p.values);
}

void write_fields(JsonWriter& json, const DeviceIdRequest& p) {
  json.field("mei", unsigned{p.mei});
  json.field("read_device_id_code", unsigned{p.read_device_id_code});
  json.field("object_id", unsigned{p.object_id});
}

void write_fields(JsonWriter& json, const DeviceIdResponse& p) {
  json.field("mei", unsigned{p.mei});
  json.field("read_device_id_code", unsigned{p.read_device_id_code});
  json.field("conformity", unsigned{p.conformity});
  json.field("more_follows", p.more_follows != 0);
  json.field("next_object_id", unsigned{p.next_object_id});
  json.field("object_count", unsigned{p.object_count});
  json.key("objects");
  json.begin_array();
  for (const DeviceIdObject& o : p.objects) {
    json.begin_object();
    json.field("id", unsigned{o.id});
    json.key("name");
    const std::string_view name = device_id_object_name(o.id);
    if (name.empty()) {
      json.null();
    } else {
      json.value(name);
    }
    json.key("value");
    write_latin1(json, o.value);
    json.end_object();
  }
  json.end_array();
}

void write_fields(JsonWriter& json, const MeiPdu& p) {
  json.field("mei", unsigned{p.mei});
  write_hex(json, "data", p.payload);
}

}  // namespace

void write_pdu_json(JsonWriter& json, const DecodedPdu& pdu) {
  std::visit([&json](const auto& p) { write_fields(json, p); }, pdu);
}

}  // namespace rtu
