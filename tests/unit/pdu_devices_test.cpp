// Every example frame of the four device documents (devices/TH900.md, YAKOTEC.md,
// YW2050.md, YW2300.md) decodes to the fields their text states.
#include <gtest/gtest.h>

#include <vector>

#include "modbus/pdu.hpp"
#include "pdu_test_support.hpp"

namespace rtu {
namespace {

using test::frame_from_hex;

std::vector<unsigned> words(WordView v) {
  std::vector<unsigned> out;
  for (std::size_t i = 0; i < v.size(); ++i) out.push_back(v[i]);
  return out;
}

// Decodes a request/response pair as the transaction tracker would hand them over. The
// decoded views point into the records, so a Pair never moves.
struct Pair {
  Pair(std::string_view request_hex, std::string_view response_hex)
      : request(frame_from_hex(request_hex)), response(frame_from_hex(response_hex)) {
    response.request = &request;
    EXPECT_TRUE(request.crc_ok) << request_hex;
    EXPECT_TRUE(response.crc_ok) << response_hex;
    req = decode_pdu(request, Role::kRequest);
    rsp = decode_pdu(response, Role::kResponse);
  }
  Pair(const Pair&) = delete;
  Pair& operator=(const Pair&) = delete;

  Record request;
  Record response;
  DecodedPdu req;
  DecodedPdu rsp;
};

void expect_read(const DecodedPdu& pdu, unsigned fc, unsigned addr, unsigned qty) {
  const auto* r = std::get_if<ReadRequest>(&pdu);
  ASSERT_NE(r, nullptr);
  EXPECT_EQ(r->function, fc);
  EXPECT_EQ(r->addr, addr);
  EXPECT_EQ(r->qty, qty);
  EXPECT_TRUE(check_pdu(pdu).empty());
}

void expect_registers(const Pair& p, std::vector<unsigned> values) {
  const auto* r = std::get_if<ReadRegistersResponse>(&p.rsp);
  ASSERT_NE(r, nullptr);
  EXPECT_EQ(words(r->values), values);
  EXPECT_TRUE(check_pdu(p.rsp).empty());
  EXPECT_TRUE(check_response_fits(p.request, p.response).empty());
}

void expect_write_single(std::string_view hex, unsigned fc, unsigned addr, unsigned value) {
  const Record f = frame_from_hex(hex);
  EXPECT_TRUE(f.crc_ok) << hex;
  for (const Role role : {Role::kRequest, Role::kResponse}) {
    const DecodedPdu pdu = decode_pdu(f, role);
    const auto* w = std::get_if<WriteSingle>(&pdu);
    ASSERT_NE(w, nullptr);
    EXPECT_EQ(w->function, fc);
    EXPECT_EQ(w->addr, addr);
    EXPECT_EQ(w->value, value);
    EXPECT_TRUE(check_pdu(pdu).empty());
  }
  // Echoed: the frame is its own response.
  EXPECT_TRUE(check_response_fits(f, f).empty());
}

void expect_write_multiple(const Pair& p, unsigned addr, unsigned qty,
                           std::vector<unsigned> values) {
  const auto* q = std::get_if<WriteMultipleRegistersRequest>(&p.req);
  ASSERT_NE(q, nullptr);
  EXPECT_EQ(q->addr, addr);
  EXPECT_EQ(q->qty, qty);
  EXPECT_EQ(words(q->values), values);
  EXPECT_TRUE(check_pdu(p.req).empty());
  const auto* r = std::get_if<WriteMultipleResponse>(&p.rsp);
  ASSERT_NE(r, nullptr);
  EXPECT_EQ(r->addr, addr);
  EXPECT_EQ(r->qty, qty);
  EXPECT_TRUE(check_pdu(p.rsp).empty());
  EXPECT_TRUE(check_response_fits(p.request, p.response).empty());
}

void expect_exception(std::string_view request_hex, std::string_view response_hex, unsigned code) {
  const Record request = frame_from_hex(request_hex);
  const DecodedPdu req = decode_pdu(request, Role::kRequest);
  EXPECT_FALSE(std::holds_alternative<RawPdu>(req)) << request_hex;
  EXPECT_TRUE(check_pdu(req).empty()) << request_hex;
  Record response = frame_from_hex(response_hex);
  EXPECT_TRUE(response.crc_ok) << response_hex;
  response.request = &request;
  const DecodedPdu rsp = decode_pdu(response, Role::kResponse);
  const auto* e = std::get_if<ExceptionResponse>(&rsp);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->function, request.function() | 0x80U);
  EXPECT_EQ(e->code, code);
  EXPECT_TRUE(check_pdu(rsp).empty());
  EXPECT_TRUE(check_response_fits(request, response).empty());
}

// ---- devices/TH900.md ----------------------------------------------------------------

TEST(PduDevicesTh900, ReadSv) {
  const Pair p("01 03 00 00 00 02 C4 0B", "01 03 04 02 BC 00 00 3A 6F");
  expect_read(p.req, 3, 0x0000, 2);
  expect_registers(p, {0x02BC, 0x0000});  // SV = 700 → 70.0
}

TEST(PduDevicesTh900, WriteSv) {
  const Pair p("01 10 00 00 00 02 04 03 E8 00 00 73 DF", "01 10 00 00 00 02 41 C8");
  expect_write_multiple(p, 0x0000, 2, {0x03E8, 0x0000});  // 1000 → 100.0
}

TEST(PduDevicesTh900, WriteSingleAndGenericRead) {
  expect_write_single("01 06 00 23 00 09 B8 06", 6, 0x0023, 9);
  const Record generic = frame_from_hex("01 03 00 10 00 02 C5 CE");
  EXPECT_TRUE(generic.crc_ok);
  expect_read(decode_pdu(generic, Role::kRequest), 3, 0x0010, 2);
}

// ---- devices/YAKOTEC.md --------------------------------------------------------------

TEST(PduDevicesYakotec, Reads) {
  const Pair one("01 03 00 23 00 01 75 C0", "01 03 02 00 3C B8 55");
  expect_read(one.req, 3, 0x0023, 1);
  expect_registers(one, {60});
  const Pair three("01 03 00 0A 00 03 25 C9", "01 03 06 00 00 13 88 00 00 A5 DB");
  expect_read(three.req, 3, 0x000A, 3);
  expect_registers(three, {0x0000, 0x1388, 0x0000});  // 5000 pulses, high word first
}

TEST(PduDevicesYakotec, WritesSingle) {
  expect_write_single("01 06 00 23 00 3C 78 11", 6, 0x0023, 60);
  expect_write_single("01 06 00 21 01 F4 D9 D7", 6, 0x0021, 500);
  expect_write_single("01 06 00 27 00 01 F8 01", 6, 0x0027, 1);
  expect_write_single("01 06 00 27 00 02 B8 00", 6, 0x0027, 2);
}

TEST(PduDevicesYakotec, WritesMultiple) {
  expect_write_multiple(Pair("01 10 00 24 00 02 04 00 00 13 88 FD 12", "01 10 00 24 00 02 01 C3"),
                        0x0024, 2, {0x0000, 0x1388});
  expect_write_multiple(
      Pair("01 10 00 1D 00 03 06 00 3C 00 64 00 64 66 DE", "01 10 00 1D 00 03 10 0E"), 0x001D, 3,
      {60, 100, 100});
}

TEST(PduDevicesYakotec, MalformedWriteFromTheSeedIsShownAndFlagged) {
  // Quantity 5 needs byte count 10; it says 12 and carries 13 data bytes.
  const Pair p("01 10 00 21 00 05 0C 00 0A 00 64 00 64 00 3C 00 00 00 03 E8 04 76",
               "01 10 00 21 00 05 50 00");
  const auto* q = std::get_if<WriteMultipleRegistersRequest>(&p.req);
  ASSERT_NE(q, nullptr);
  EXPECT_EQ(q->addr, 0x0021);
  EXPECT_EQ(q->qty, 5);
  EXPECT_EQ(q->byte_count, 12);
  // The 12 bytes the byte count announces are shown; the 13th byte is not a value.
  EXPECT_EQ(words(q->values),
            (std::vector<unsigned>{0x000A, 0x0064, 0x0064, 0x003C, 0x0000, 0x0003}));
  EXPECT_TRUE(q->issues.has(IssueId::kByteCount));  // 13 bytes present, 12 announced
  const IssueSet issues = check_pdu(p.req);
  EXPECT_TRUE(issues.has(IssueId::kByteCount));
  EXPECT_FALSE(issues.has(IssueId::kBadQuantity));
  // The response is well-formed and echoes address and quantity.
  EXPECT_TRUE(check_pdu(p.rsp).empty());
  EXPECT_TRUE(check_response_fits(p.request, p.response).empty());
}

TEST(PduDevicesYakotec, VendorExceptions) {
  // Code 01 answers a CRC error: the request's CRC is wrong (85 C0 is right), and it still
  // decodes, since the decoder never trusts or needs the CRC.
  EXPECT_FALSE(frame_from_hex("01 03 00 20 00 01 85 C1").crc_ok);
  expect_exception("01 03 00 20 00 01 85 C1", "01 83 01 80 F0", 1);
  expect_exception("01 02 00 00 00 04 79 C9", "01 82 02 C1 61", 2);
  expect_exception("01 03 00 3C 00 01 44 06", "01 83 03 01 31", 3);
  expect_exception("01 06 FF 00 FF FF B8 6E", "01 86 04 43 A3", 4);
  expect_exception("01 03 00 20 00 20 45 D8", "01 83 05 81 33", 5);
  expect_exception("01 06 00 00 00 01 48 0A", "01 86 06 C2 62", 6);
  expect_exception("01 06 00 20 FF FF 89 B0", "01 86 07 03 A2", 7);
}

// ---- devices/YW2050.md ---------------------------------------------------------------

TEST(PduDevicesYw2050, ReadThreeFrom0032) {
  const Pair p("01 03 00 32 00 03 A4 04", "01 03 06 EA 60 C3 50 DB 6C D1 3F");
  expect_read(p.req, 3, 0x0032, 3);
  expect_registers(p, {0xEA60, 0xC350, 0xDB6C});
}

TEST(PduDevicesYw2050, Writes) {
  expect_write_single("01 06 00 02 00 02 A9 CB", 6, 0x0002, 2);
  expect_write_multiple(Pair("01 10 00 00 00 02 04 00 64 00 00 B2 70", "01 10 00 00 00 02 41 C8"),
                        0x0000, 2, {100, 0});
}

// ---- devices/YW2300.md ---------------------------------------------------------------

TEST(PduDevicesYw2300, ReadOutputsAndInputs) {
  const Pair out("01 01 00 00 00 03 7C 0B", "01 01 01 03 11 89");
  expect_read(out.req, 1, 0x0000, 3);
  const auto* coils = std::get_if<ReadBitsResponse>(&out.rsp);
  ASSERT_NE(coils, nullptr);
  ASSERT_EQ(coils->bits.size(), 3U);  // trimmed to the request's quantity
  EXPECT_TRUE(coils->bits[0]);
  EXPECT_TRUE(coils->bits[1]);
  EXPECT_FALSE(coils->bits[2]);
  EXPECT_TRUE(check_response_fits(out.request, out.response).empty());

  const Pair in("01 02 00 00 00 07 39 C8", "01 02 01 1F E0 40");
  expect_read(in.req, 2, 0x0000, 7);
  const auto* inputs = std::get_if<ReadBitsResponse>(&in.rsp);
  ASSERT_NE(inputs, nullptr);
  ASSERT_EQ(inputs->bits.size(), 7U);
  for (std::size_t i = 0; i < 5; ++i) EXPECT_TRUE(inputs->bits[i]) << i;  // 1F: DI1-DI5 on
  EXPECT_FALSE(inputs->bits[5]);
  EXPECT_FALSE(inputs->bits[6]);
  EXPECT_TRUE(check_response_fits(in.request, in.response).empty());
}

TEST(PduDevicesYw2300, ReadCurrents) {
  const Pair p("01 03 01 06 00 03 E4 36", "01 03 06 13 88 13 88 13 88 4A 31");
  expect_read(p.req, 3, 0x0106, 3);
  expect_registers(p, {5000, 5000, 5000});
}

TEST(PduDevicesYw2300, Writes) {
  expect_write_single("01 05 00 00 FF 00 8C 3A", 5, 0x0000, 0xFF00);
  expect_write_single("01 06 54 51 00 03 88 2A", 6, 0x5451, 3);
  expect_write_multiple(Pair("01 10 54 50 00 02 04 00 01 00 03 29 91", "01 10 54 50 00 02 51 E9"),
                        0x5450, 2, {1, 3});
}

}  // namespace
}  // namespace rtu
