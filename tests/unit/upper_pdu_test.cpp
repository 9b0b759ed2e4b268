#include "capture/upper_pdu.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <optional>
#include <random>
#include <string>
#include <vector>

#include "capture/rtac_serial.hpp"

namespace rtu {
namespace {

using Bytes = std::vector<std::uint8_t>;
const Bytes kAdu = {0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD};

TEST(UpperPdu, MinimalRecordMatchesWiresharksLayout) {
  Bytes out;
  build_upper_pdu(kAdu, {}, out);
  const Bytes expected = {0x00, 0x0C, 0x00, 0x08, 'm',  'b',  'r',  't',  'u',  0x00, 0x00, 0x00,
                          0x00, 0x00, 0x00, 0x00, 0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD};
  EXPECT_EQ(out, expected);
}

TEST(UpperPdu, DirectionTravelsAsPorts) {
  for (const auto direction : {PduDirection::kRequest, PduDirection::kResponse}) {
    Bytes out;
    build_upper_pdu(kAdu, {"mbrtu", direction, ""}, out);
    // name (12) + 3 × u32 tags (24) + end (4) + ADU
    EXPECT_EQ(out.size(), 12U + 24U + 4U + kAdu.size());
    std::string error;
    UpperPdu pdu;
    ASSERT_TRUE(parse_upper_pdu(out, pdu, error)) << error;
    EXPECT_EQ(pdu.dissector, "mbrtu");
    EXPECT_EQ(pdu.port_type, upper_pdu::kPortTypeTcp);
    EXPECT_EQ(pdu.source_port, direction == PduDirection::kRequest ? 1U : 502U);
    EXPECT_EQ(pdu.destination_port, direction == PduDirection::kRequest ? 502U : 1U);
    EXPECT_EQ(pdu.direction(), direction);
    EXPECT_EQ(Bytes(pdu.payload.begin(), pdu.payload.end()), kAdu);
  }
}

TEST(UpperPdu, ProtocolColumnAndUnpaddedNames) {
  Bytes out;
  build_upper_pdu(kAdu, {"mbrtu", PduDirection::kUnknown, "Modbus RTU"}, out);
  std::string error;
  UpperPdu pdu;
  ASSERT_TRUE(parse_upper_pdu(out, pdu, error)) << error;
  EXPECT_EQ(pdu.protocol_column, "Modbus RTU");
  EXPECT_EQ(pdu.direction(), PduDirection::kUnknown);
  // Other writers may use unpadded names and tags we do not know (IPv4 source here).
  const Bytes foreign = {0x00, 0x14, 0x00, 0x04, 10,   0,    0,   1,   0x00,
                         0x0C, 0x00, 0x05, 'm',  'b',  'r',  't', 'u', 0x00,
                         0x00, 0x00, 0x00, 0x01, 0x07, 0xE2, 0x41};
  ASSERT_TRUE(parse_upper_pdu(foreign, pdu, error)) << error;
  EXPECT_EQ(pdu.dissector, "mbrtu");
  EXPECT_TRUE(pdu.protocol_column.empty());  // nothing of the record parsed before is left
  EXPECT_EQ(pdu.payload.size(), 4U);
}

TEST(UpperPdu, MalformedTlvsSayWhere) {
  Bytes out;
  build_upper_pdu(kAdu, {}, out);
  std::string error;
  UpperPdu pdu;
  // Cut inside the TLV list (before the end tag's 4 bytes are complete).
  for (std::size_t cut = 0; cut < 16; ++cut) {
    EXPECT_FALSE(parse_upper_pdu(std::span(out).first(cut), pdu, error)) << cut;
    EXPECT_NE(error.find("byte "), std::string::npos);
  }
  Bytes long_tag = out;
  long_tag[3] = 0xF0;
  EXPECT_FALSE(parse_upper_pdu(long_tag, pdu, error));
  EXPECT_EQ(error, "byte 0: tag 12 of length 240 runs past the end of the record");
}

// Everything a parse says, as text, to compare two parses of the same record.
std::string described(bool ok, const UpperPdu& pdu, const std::string& error,
                      std::span<const std::uint8_t> record) {
  if (!ok) return fmt::format("error: {}", error);
  const auto port = [](const std::optional<std::uint32_t>& p) {
    return p ? fmt::format("{}", *p) : std::string("-");
  };
  return fmt::format("dissector '{}' column '{}' ports {} {} {} payload at {} of {}", pdu.dissector,
                     pdu.protocol_column, port(pdu.port_type), port(pdu.source_port),
                     port(pdu.destination_port), pdu.payload.data() - record.data(),
                     pdu.payload.size());
}

// The reader that remembers headers answers every record as parse_upper_pdu() does: on a mix
// of rtuscope's headers (requests, answers, unknown roles, a protocol column, the 'data'
// dissector), a header too long to remember, and damaged records in between.
TEST(UpperPdu, RememberedHeadersAnswerAsAParseOfEachRecord) {
  std::mt19937 random(7);
  const std::string long_column(60, 'x');  // UpperPduBuild views it
  const std::vector<UpperPduBuild> builds = {
      {"mbrtu", PduDirection::kRequest, ""}, {"mbrtu", PduDirection::kResponse, ""},
      {"mbrtu", PduDirection::kUnknown, ""}, {"mbrtu", PduDirection::kUnknown, "Modbus RTU"},
      {"data", PduDirection::kUnknown, ""},  {"mbrtu", PduDirection::kRequest, long_column},
  };
  UpperPduReader reader;
  int remembered_answers = 0;
  for (int i = 0; i < 5000; ++i) {
    Bytes payload(random() % 20);
    for (auto& b : payload) b = static_cast<std::uint8_t>(random());
    Bytes record;
    build_upper_pdu(payload, builds[random() % builds.size()], record);
    if (random() % 10 == 0) {
      // Damaged: a byte of the header changed, or the record cut short.
      if (random() % 2 == 0 && record.size() > 24) {
        record[random() % 24] ^= static_cast<std::uint8_t>(1U + random() % 255);
      } else {
        record.resize(random() % record.size());
      }
    }
    UpperPdu expected_pdu;
    std::string expected_error;
    const bool expected_ok = parse_upper_pdu(record, expected_pdu, expected_error);
    UpperPdu pdu;
    std::string error;
    const bool ok = reader.parse(record, pdu, error);
    ASSERT_EQ(described(ok, pdu, error, record),
              described(expected_ok, expected_pdu, expected_error, record))
        << "record " << i;
    // The answer does not lean on the record's own bytes for its texts.
    if (ok && !pdu.dissector.empty() &&
        (pdu.dissector.data() < reinterpret_cast<const char*>(record.data()) ||
         pdu.dissector.data() >= reinterpret_cast<const char*>(record.data() + record.size()))) {
      ++remembered_answers;
    }
  }
  // Most records repeat one of the last two headers.
  EXPECT_GT(remembered_answers, 1000);
}

TEST(UpperPdu, WhatMbrtuDeclines) {
  EXPECT_FALSE(mbrtu_declines(kAdu));
  EXPECT_TRUE(mbrtu_declines(Bytes{0x00, 0x06, 0x00, 0x01, 0x00, 0x03, 0x98, 0x1A}));
  EXPECT_TRUE(mbrtu_declines(Bytes{0x01, 0x07, 0x41, 0xE2}));
}

TEST(RtacSerial, HeaderRoundTrip) {
  Bytes out;
  const Bytes payload = {0x55};
  build_rtac_record(1'700'000'000'123'456'789, RtacEvent::kParityError,
                    rtac_lines::kCts | rtac_lines::kMbok, payload, out);
  const Bytes header = {0x65, 0x53, 0xF1, 0x00, 0x00, 0x01, 0xE2, 0x40, 0x08, 0x41, 0x00, 0x00};
  ASSERT_EQ(out.size(), 13U);
  EXPECT_EQ(Bytes(out.begin(), out.begin() + 12), header);
  std::string error;
  const auto rec = parse_rtac_record(out, error);
  ASSERT_TRUE(rec) << error;
  EXPECT_EQ(rec->seconds, 1'700'000'000U);
  EXPECT_EQ(rec->micros, 123'456U);
  EXPECT_EQ(rec->header_time(), 1'700'000'000'123'456'000);
  EXPECT_EQ(rec->event, 0x08);
  EXPECT_EQ(rec->control_lines, 0x41);
  EXPECT_EQ(rec->payload.size(), 1U);
  EXPECT_EQ(rec->payload[0], 0x55);
}

TEST(RtacSerial, ShortRecordIsAnError) {
  std::string error;
  EXPECT_FALSE(parse_rtac_record(Bytes(11, 0), error));
  EXPECT_EQ(error, "RTAC serial record of 11 bytes is shorter than its 12-byte header");
  EXPECT_TRUE(parse_rtac_record(Bytes(12, 0), error));  // an event with no payload
}

TEST(RtacSerial, EventNamesAsWiresharkShowsThem) {
  EXPECT_EQ(rtac_event_name(0x02), "DATA_RX_START");
  EXPECT_EQ(rtac_event_name(0x05), "CAPTURE_DATA_LOST");
  EXPECT_EQ(rtac_event_name(0x07), "FRAMING_ERROR");
  EXPECT_EQ(rtac_event_name(0x08), "PARITY_ERROR");
  EXPECT_EQ(rtac_event_name(0x09), "SERIAL_BREAK_EVENT");
  EXPECT_EQ(rtac_event_name(0x0A), "SERIAL_OVERFLOW_EVENT");
  EXPECT_EQ(rtac_event_name(0x0B), "UNKNOWN");
}

}  // namespace
}  // namespace rtu
