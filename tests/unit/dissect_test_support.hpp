#pragma once
// Helpers for the device-dissector tests: frames from hex, a library of the bundled maps,
// and a request/response runner through the device stage.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/crc16.hpp"
#include "dissect/device_stage.hpp"
#include "dissect/map_library.hpp"
#include "dissect/point_format.hpp"
#include "framing/record.hpp"

namespace rtu::dissect::testing {

inline std::vector<std::uint8_t> parse_hex(std::string_view hex) {
  std::vector<std::uint8_t> out;
  int hi = -1;
  for (const char c : hex) {
    int v = -1;
    if (c >= '0' && c <= '9') v = c - '0';
    if (c >= 'a' && c <= 'f') v = c - 'a' + 10;
    if (c >= 'A' && c <= 'F') v = c - 'A' + 10;
    if (v < 0) continue;
    if (hi < 0) {
      hi = v;
    } else {
      out.push_back(static_cast<std::uint8_t>(hi * 16 + v));
      hi = -1;
    }
  }
  return out;
}

// A frame from its full hex (CRC included, as the manuals print them).
inline Record frame(std::string_view hex, Role role, std::uint64_t seq) {
  const auto bytes = parse_hex(hex);
  if (bytes.size() > kMaxAdu) throw std::invalid_argument("frame too long");
  Record r;
  r.seq = seq;
  r.size = static_cast<std::uint16_t>(bytes.size());
  std::copy(bytes.begin(), bytes.end(), r.storage.begin());
  r.crc_ok = crc16_valid(r.bytes());
  r.role = role;
  return r;
}

// A frame from hex without CRC: the CRC is appended (for frames made up by a test).
inline Record made_frame(std::string_view hex, Role role, std::uint64_t seq) {
  auto bytes = parse_hex(hex);
  const std::uint16_t crc = crc16(bytes);
  bytes.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  bytes.push_back(static_cast<std::uint8_t>(crc >> 8U));
  std::string full;
  for (const auto b : bytes) full += fmt::format("{:02x}", b);
  return frame(full, role, seq);
}

inline const MapLibrary& bundled_maps() {
  static const MapLibrary lib = [] {
    MapLibrary l;
    const auto errors = l.load_dir(RTUSCOPE_SOURCE_DIR "/dissectors");
    for (const auto& e : errors) ADD_FAILURE() << e;
    return l;
  }();
  return lib;
}

// A range of a space: `length` units (a read's quantity) or bytes, as the test counts.
struct SpaceRange {
  const Space* space;
  std::uint32_t start;
  std::uint32_t length;
};

// Ranges around every point of every bundled map's spaces: starting before, at, inside and
// after each point, 1 to 24 long. Far more than a decoder's remembering table holds.
inline std::vector<SpaceRange> ranges_around_bundled_points() {
  std::vector<SpaceRange> ranges;
  for (const auto& map : bundled_maps().maps()) {
    for (const Space& space : map->spaces) {
      for (const Point& p : space.points) {
        for (std::uint32_t back = 0; back <= 2; ++back) {
          if (p.addr < back) continue;
          for (std::uint32_t length = 1; length <= 24; ++length) {
            ranges.push_back({&space, p.addr - back, length});
            ranges.push_back({&space, p.addr + back + 1, length});
          }
        }
      }
    }
  }
  return ranges;
}

// The k-th of `n` items in three passes (k below 3n) that ask each one again after others:
// forwards, backwards, then every seventh.
inline std::size_t asked_again_order(std::size_t k, std::size_t n) {
  const std::size_t pass = k / n;
  const std::size_t i = k % n;
  return pass == 0 ? i : pass == 1 ? n - 1 - i : (i * 7) % n;
}

inline const DecodedPoint* find_point(const Decoded& d, std::string_view name) {
  for (const auto& p : d.points) {
    if (p.point != nullptr && p.spare_index == 0 && p.point->name == name) return &p;
  }
  return nullptr;
}

// Keeps a copy of what the device stage hung on the last record.
class LastReading : public RecordSink {
 public:
  void on_record(Record& r) override {
    decoded = r.device != nullptr ? r.device->decoded : Decoded{};
    has_map = r.device != nullptr && r.device->map != nullptr;
  }
  Decoded decoded;
  bool has_map = false;
};

// Drives one slave of one model through request/response pairs.
class Bus {
 public:
  explicit Bus(std::string_view model, std::uint8_t slave = 1) {
    const DeviceMap* map = bundled_maps().find(model);
    if (map == nullptr) throw std::invalid_argument("no bundled map " + std::string(model));
    table_.assign(slave, *map, ModelOrigin::kConfigured);
  }

  // Runs a request through the stage; returns what it decoded (a copy, so it outlives the
  // next frame).
  Decoded request(const Record& req) {
    last_request_ = req;
    stage_.on_record(last_request_);
    issues_ = last_request_.issues;
    request_text_.clear();
    if (last_.has_map) append_points_text(request_text_, last_.decoded);
    return last_.decoded;
  }
  // Runs a response to the last request through the stage, and renders it as the writers do.
  Decoded response(Record resp) {
    resp.request = &last_request_;
    stage_.on_record(resp);
    issues_ = resp.issues;
    text_.clear();
    json_.clear();
    JsonWriter json(json_);
    json.begin_object();
    if (last_.has_map) {
      append_points_text(text_, last_.decoded);
      json.field("device", std::string_view(last_.decoded.map->model));
      if (!last_.decoded.points.empty()) write_points_json(json, last_.decoded);
    }
    json.end_object();
    return last_.decoded;
  }
  Decoded exchange(std::string_view req_hex, std::string_view resp_hex) {
    request(frame(req_hex, Role::kRequest, seq_++));
    return response(frame(resp_hex, Role::kResponse, seq_++));
  }
  Decoded request_hex(std::string_view hex) { return request(frame(hex, Role::kRequest, seq_++)); }

  [[nodiscard]] const IssueSet& issues() const { return issues_; }
  [[nodiscard]] const Record& last_request() const { return last_request_; }
  [[nodiscard]] std::string text() const { return fmt::to_string(text_); }
  [[nodiscard]] std::string json() const { return fmt::to_string(json_); }
  // The text of the last request's points, as the text writer shows them.
  [[nodiscard]] std::string request_text() const { return fmt::to_string(request_text_); }
  DeviceTable& table() { return table_; }
  std::uint64_t next_seq() { return seq_++; }

 private:
  DeviceTable table_;
  LastReading last_;
  DeviceStage stage_{table_, last_};
  Record last_request_;
  fmt::memory_buffer request_text_;
  IssueSet issues_;
  fmt::memory_buffer text_;
  fmt::memory_buffer json_;
  std::uint64_t seq_ = 0;
};

}  // namespace rtu::dissect::testing
