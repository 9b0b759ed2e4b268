// Writes capture files with rtuscope's pcap/pcapng writers, plus a JSON-lines file that
// states what each record holds, for check_fixtures.py to compare with tshark's reading.
//   fixture_writer OUT_DIR
#include <fmt/format.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "capture/byte_output.hpp"
#include "capture/pcap_format.hpp"
#include "capture/pcap_writer.hpp"
#include "capture/pcapng_writer.hpp"
#include "capture/rtac_serial.hpp"
#include "capture/upper_pdu.hpp"
#include "core/crc16.hpp"

namespace {

using Bytes = std::vector<std::uint8_t>;
using rtu::PduDirection;

struct Frame {
  Bytes adu;  // CRC appended by with_crc()
  PduDirection direction;
  std::string comment;
  int request_index = -1;  // for responses: index of the request in the list
};

Bytes with_crc(Bytes pdu, bool corrupt = false) {
  const std::uint16_t crc = rtu::crc16(pdu);
  pdu.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  pdu.push_back(static_cast<std::uint8_t>((crc >> 8U) ^ (corrupt ? 0x5AU : 0U)));
  return pdu;
}

std::vector<Frame> frames() {
  std::vector<Frame> f;
  const auto add = [&](Bytes adu, PduDirection d, std::string comment = "", int request = -1) {
    f.push_back({std::move(adu), d, std::move(comment), request});
    return static_cast<int>(f.size()) - 1;
  };
  const auto req = PduDirection::kRequest;
  const auto rsp = PduDirection::kResponse;
  // FC03 read 10 registers from 0x006B, and its answer.
  int r = add(with_crc({0x01, 0x03, 0x00, 0x6B, 0x00, 0x03}), req);
  add(with_crc({0x01, 0x03, 0x06, 0x02, 0x2B, 0x00, 0x00, 0x00, 0x64}), rsp, "", r);
  // Bad CRC on a request; the comment lists the issue.
  add(with_crc({0x02, 0x03, 0x00, 0x00, 0x00, 0x02}, true), req, "issues: crc");
  // FC06 echo: Wireshark cannot tell request from response without the ports.
  r = add(with_crc({0x11, 0x06, 0x00, 0x01, 0x00, 0x03}), req);
  add(with_crc({0x11, 0x06, 0x00, 0x01, 0x00, 0x03}), rsp, "", r);
  // Exception response (illegal data address).
  r = add(with_crc({0x01, 0x04, 0x10, 0x00, 0x00, 0x01}), req);
  add(with_crc({0x01, 0x84, 0x02}), rsp, "exception 2 ILLEGAL DATA ADDRESS", r);
  // Broadcast: mbrtu declines unit 0; it must still appear, with a comment.
  add(with_crc({0x00, 0x06, 0x00, 0x10, 0x00, 0x01}), req,
      "broadcast (unit 0): Wireshark does not dissect it as Modbus");
  // 4-byte request (FC07): mbrtu declines frames under 5 bytes.
  r = add(with_crc({0x0A, 0x07}), req, "4-byte frame: Wireshark does not dissect it as Modbus");
  add(with_crc({0x0A, 0x07, 0x6D}), rsp, "", r);
  // FC16 write 2 registers, and the answer.
  r = add(with_crc({0x03, 0x10, 0x00, 0x01, 0x00, 0x02, 0x04, 0x00, 0x0A, 0x01, 0x02}), req);
  add(with_crc({0x03, 0x10, 0x00, 0x01, 0x00, 0x02}), rsp, "", r);
  // FC05 echo, the response with a bad CRC and a multi-issue comment.
  r = add(with_crc({0x04, 0x05, 0x00, 0xAC, 0xFF, 0x00}), req);
  add(with_crc({0x04, 0x05, 0x00, 0xAC, 0xFF, 0x00}, true), rsp, "issues: crc, t3.5", r);
  return f;
}

struct RawEvent {
  rtu::RtacEvent event;
  Bytes payload;
};

std::vector<RawEvent> raw_events() {
  return {{rtu::RtacEvent::kDataRxStart, {0x01, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x74, 0x17}},
          {rtu::RtacEvent::kParityError, {0x55}},
          {rtu::RtacEvent::kFramingError, {0x00}},
          {rtu::RtacEvent::kSerialBreak, {}},
          {rtu::RtacEvent::kSerialOverflow, {}},
          {rtu::RtacEvent::kCaptureDataLost, {}},
          {rtu::RtacEvent::kDataRxStart, {0x01, 0x03, 0x06}}};
}

constexpr rtu::Nanos kStart = 1'700'000'000'000'000'000;
// Odd nanoseconds so ns resolution is visible; 20 ms apart.
rtu::Nanos frame_time(std::size_t i) {
  return kStart + static_cast<rtu::Nanos>(i) * 20'000'000 + 123'457;
}

std::string hex(const Bytes& b) {
  std::string s;
  for (const auto x : b) s += fmt::format("{:02x}", x);
  return s;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::uint32_t flags_of(PduDirection d) {
  return d == PduDirection::kRequest ? rtu::pcap::kFlagsOutbound : rtu::pcap::kFlagsInbound;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fixture_writer OUT_DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  const auto list = frames();
  Bytes record;

  // 1. Decoded frames, pcapng, ns.
  {
    rtu::PcapngWriter w(std::make_unique<rtu::FileOutput>(dir + "/frames.pcapng"));
    const auto id =
        w.add_interface({rtu::pcap::kLinkTypeUpperPdu, "/dev/ttyUSB0", "RS-485 9600 8E1", 9, 0});
    for (std::size_t i = 0; i < list.size(); ++i) {
      const bool declined = rtu::mbrtu_declines(list[i].adu);
      rtu::build_upper_pdu(list[i].adu, {"mbrtu", list[i].direction, declined ? "Modbus RTU" : ""},
                           record);
      w.write_packet(id, frame_time(i), record, {list[i].comment, flags_of(list[i].direction), 0});
    }
  }
  // 2. The same frames in classic pcap (ns and µs), big-endian for the µs one.
  {
    rtu::PcapWriter ns(std::make_unique<rtu::FileOutput>(dir + "/frames_ns.pcap"),
                       rtu::pcap::kLinkTypeUpperPdu, rtu::PcapResolution::kNanos);
    rtu::PcapWriter us(std::make_unique<rtu::FileOutput>(dir + "/frames_us_be.pcap"),
                       rtu::pcap::kLinkTypeUpperPdu, rtu::PcapResolution::kMicros,
                       rtu::ByteOrder::kBig);
    for (std::size_t i = 0; i < list.size(); ++i) {
      rtu::build_upper_pdu(list[i].adu, {"mbrtu", list[i].direction, ""}, record);
      ns.write_packet(frame_time(i), record);
      us.write_packet(frame_time(i), record);
    }
  }
  // 3. Frames on interface 0 and raw events on interface 1 (µs) of one big-endian pcapng.
  const auto events = raw_events();
  {
    rtu::PcapngWriter w(std::make_unique<rtu::FileOutput>(dir + "/mixed.pcapng"),
                        rtu::ByteOrder::kBig);
    const auto frames_id = w.add_interface({rtu::pcap::kLinkTypeUpperPdu, "frames", "", 9, 0});
    const auto raw_id = w.add_interface({rtu::pcap::kLinkTypeRtacSerial, "raw", "", 6, 0});
    for (std::size_t i = 0; i < events.size(); ++i) {
      const rtu::Nanos t = frame_time(i);
      rtu::build_rtac_record(t, events[i].event, 0, events[i].payload, record);
      w.write_packet(raw_id, t, record,
                     {events[i].event == rtu::RtacEvent::kDataRxStart ? "" : "line event", 0, 0});
      if (i < list.size()) {
        rtu::build_upper_pdu(list[i].adu, {"mbrtu", list[i].direction, ""}, record);
        w.write_packet(frames_id, t + 1, record, {"", flags_of(list[i].direction), 0});
      }
    }
  }

  std::FILE* out = std::fopen((dir + "/expected.jsonl").c_str(), "w");
  if (out == nullptr) return 2;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const Frame& f = list[i];
    fmt::print(out,
               "{{\"kind\":\"frame\",\"n\":{},\"t_ns\":{},\"hex\":\"{}\",\"direction\":\"{}\","
               "\"comment\":{},\"crc_ok\":{},\"dissected\":{},\"request_n\":{}}}\n",
               i + 1, frame_time(i), hex(f.adu),
               f.direction == PduDirection::kRequest ? "request" : "response",
               json_string(f.comment), rtu::crc16_valid(f.adu), !rtu::mbrtu_declines(f.adu),
               f.request_index < 0 ? 0 : f.request_index + 1);
  }
  for (std::size_t i = 0; i < events.size(); ++i) {
    fmt::print(out,
               "{{\"kind\":\"event\",\"n\":{},\"t_ns\":{},\"event\":{},\"name\":\"{}\","
               "\"hex\":\"{}\"}}\n",
               i + 1, frame_time(i), static_cast<int>(events[i].event),
               rtu::rtac_event_name(static_cast<std::uint8_t>(events[i].event)),
               hex(events[i].payload));
  }
  std::fclose(out);
  return 0;
}
