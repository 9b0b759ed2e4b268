// decode_pdu() for every public function code in both roles. Frames are the examples of
// MODBUS Application Protocol V1.1b3 §6 (slave 0x11), with the CRC computed here.
#include <gtest/gtest.h>

#include <deque>
#include <vector>

#include "modbus/pdu.hpp"
#include "pdu_test_support.hpp"

namespace rtu {
namespace {

using test::frame_from_hex;
using test::frame_with_crc;

// A copy of the alternative (the decoded views still point into the Record).
template <typename T>
T as(const DecodedPdu& pdu) {
  const T* p = std::get_if<T>(&pdu);
  EXPECT_NE(p, nullptr) << "variant holds alternative " << pdu.index();
  return p != nullptr ? *p : T{};
}

// Decoded views point into their Record: frames built inline are kept alive here for the
// rest of the test run.
const Record& kept(std::string_view address_and_pdu_hex) {
  static std::deque<Record> frames;
  frames.push_back(frame_with_crc(address_and_pdu_hex));
  return frames.back();
}

using test::bits;
using test::words;

std::vector<unsigned> bytes(std::span<const std::uint8_t> s) {
  return {s.begin(), s.end()};
}

TEST(PduDecode, HeaderCarriesSlaveFunctionRoleAndPayload) {
  const Record f = frame_with_crc("11 03 00 6B 00 03");
  const DecodedPdu pdu = decode_pdu(f, Role::kRequest);
  const PduHeader& h = pdu_header(pdu);
  EXPECT_EQ(h.slave, 0x11);
  EXPECT_EQ(h.function, 0x03);
  EXPECT_EQ(h.role, Role::kRequest);
  EXPECT_EQ(bytes(h.data), (std::vector<unsigned>{0x00, 0x6B, 0x00, 0x03}));
  EXPECT_TRUE(h.issues.empty());
}

TEST(PduDecode, ReadCoils) {
  const Record req = frame_with_crc("11 01 00 13 00 13");
  const auto q = as<ReadRequest>(decode_pdu(req, Role::kRequest));
  EXPECT_EQ(q.addr, 0x13);
  EXPECT_EQ(q.qty, 19);

  Record rsp = frame_with_crc("11 01 03 CD 6B 05");
  const DecodedPdu alone = decode_pdu(rsp, Role::kResponse);
  const auto r = as<ReadBitsResponse>(alone);
  EXPECT_EQ(r.byte_count, 3);
  EXPECT_EQ(r.bits.size(), 24U);  // no request known: every bit of the bytes
  EXPECT_FALSE(r.addr.has_value());

  rsp.request = &req;
  const DecodedPdu paired = decode_pdu(rsp, Role::kResponse);
  const auto p = as<ReadBitsResponse>(paired);
  EXPECT_EQ(p.addr, 0x13);
  EXPECT_EQ(p.qty, 19);
  // CD = 1100 1101: coils 20..27 LSB first are 1 0 1 1 0 0 1 1.
  EXPECT_EQ(bits(p.bits),
            (std::vector<int>{1, 0, 1, 1, 0, 0, 1, 1, 1, 1, 0, 1, 0, 1, 1, 0, 1, 0, 1}));
  EXPECT_TRUE(p.issues.empty());
}

TEST(PduDecode, ReadDiscreteInputs) {
  const Record req = frame_with_crc("11 02 00 C4 00 16");
  const auto q = as<ReadRequest>(decode_pdu(req, Role::kRequest));
  EXPECT_EQ(q.function, 0x02);
  EXPECT_EQ(q.addr, 0xC4);
  EXPECT_EQ(q.qty, 22);
  Record rsp = frame_with_crc("11 02 03 AC DB 35");
  rsp.request = &req;
  const auto r = as<ReadBitsResponse>(decode_pdu(rsp, Role::kResponse));
  EXPECT_EQ(r.bits.size(), 22U);
  EXPECT_TRUE(r.bits[2]);  // AC = 1010 1100: bit 2 set
  EXPECT_FALSE(r.bits[0]);
}

TEST(PduDecode, ReadHoldingRegisters) {
  const Record req = frame_with_crc("11 03 00 6B 00 03");
  const auto q = as<ReadRequest>(decode_pdu(req, Role::kRequest));
  EXPECT_EQ(q.addr, 0x6B);
  EXPECT_EQ(q.qty, 3);
  Record rsp = frame_with_crc("11 03 06 02 2B 00 00 00 64");
  rsp.request = &req;
  const auto r = as<ReadRegistersResponse>(decode_pdu(rsp, Role::kResponse));
  EXPECT_EQ(r.byte_count, 6);
  EXPECT_EQ(words(r.values), (std::vector<unsigned>{0x022B, 0x0000, 0x0064}));
  EXPECT_EQ(r.addr, 0x6B);
  EXPECT_EQ(r.qty, 3);
}

TEST(PduDecode, ReadInputRegisters) {
  const Record req = frame_with_crc("11 04 00 08 00 01");
  EXPECT_EQ(as<ReadRequest>(decode_pdu(req, Role::kRequest)).addr, 8);
  const Record rsp = frame_with_crc("11 04 02 00 0A");
  EXPECT_EQ(words(as<ReadRegistersResponse>(decode_pdu(rsp, Role::kResponse)).values),
            (std::vector<unsigned>{0x000A}));
}

TEST(PduDecode, ContextIgnoredWhenRequestIsAnotherFunction) {
  const Record req = frame_with_crc("11 04 00 08 00 01");
  Record rsp = frame_with_crc("11 03 02 00 0A");
  rsp.request = &req;
  const auto r = as<ReadRegistersResponse>(decode_pdu(rsp, Role::kResponse));
  EXPECT_FALSE(r.addr.has_value());
}

TEST(PduDecode, WriteSingleCoilBothRoles) {
  const Record f = frame_with_crc("11 05 00 AC FF 00");
  for (const Role role : {Role::kRequest, Role::kResponse}) {
    const auto w = as<WriteSingle>(decode_pdu(f, role));
    EXPECT_EQ(w.role, role);
    EXPECT_EQ(w.addr, 0xAC);
    EXPECT_EQ(w.value, 0xFF00);
    EXPECT_EQ(w.coil(), true);
  }
  const auto off = as<WriteSingle>(decode_pdu(kept("11 05 00 AC 00 00"), Role::kRequest));
  EXPECT_EQ(off.coil(), false);
  const auto bad = as<WriteSingle>(decode_pdu(kept("11 05 00 AC 12 34"), Role::kRequest));
  EXPECT_FALSE(bad.coil().has_value());
}

TEST(PduDecode, WriteSingleRegisterBothRoles) {
  const Record f = frame_from_hex("11 06 00 01 00 03 9A 9B");  // spec example, CRC as printed
  ASSERT_TRUE(f.crc_ok);
  for (const Role role : {Role::kRequest, Role::kResponse}) {
    const auto w = as<WriteSingle>(decode_pdu(f, role));
    EXPECT_EQ(w.addr, 1);
    EXPECT_EQ(w.value, 3);
  }
}

TEST(PduDecode, ReadExceptionStatus) {
  EXPECT_TRUE(std::holds_alternative<NoDataRequest>(decode_pdu(kept("11 07"), Role::kRequest)));
  const auto r = as<ExceptionStatusResponse>(decode_pdu(kept("11 07 6D"), Role::kResponse));
  EXPECT_EQ(r.status, 0x6D);
}

TEST(PduDecode, DiagnosticsBothRoles) {
  const Record f = frame_with_crc("11 08 00 00 A5 37");
  for (const Role role : {Role::kRequest, Role::kResponse}) {
    const auto d = as<DiagnosticsPdu>(decode_pdu(f, role));
    EXPECT_EQ(d.sub_function, 0);
    EXPECT_EQ(bytes(d.payload), (std::vector<unsigned>{0xA5, 0x37}));
  }
  // Return Bus Message Count answers a counter.
  const auto counter = as<DiagnosticsPdu>(decode_pdu(kept("11 08 00 0B 01 2C"), Role::kResponse));
  EXPECT_EQ(counter.sub_function, 0x0B);
  EXPECT_TRUE(counter.issues.empty());
  // Return Query Data echoes any length.
  const auto query = as<DiagnosticsPdu>(decode_pdu(kept("11 08 00 00 01 02 03"), Role::kRequest));
  EXPECT_EQ(query.payload.size(), 3U);
  EXPECT_TRUE(query.issues.empty());
}

TEST(PduDecode, GetCommEventCounter) {
  EXPECT_TRUE(std::holds_alternative<NoDataRequest>(decode_pdu(kept("11 0B"), Role::kRequest)));
  const auto r =
      as<CommEventCounterResponse>(decode_pdu(kept("11 0B FF FF 01 08"), Role::kResponse));
  EXPECT_EQ(r.status, 0xFFFF);
  EXPECT_EQ(r.event_count, 0x0108);
}

TEST(PduDecode, GetCommEventLog) {
  EXPECT_TRUE(std::holds_alternative<NoDataRequest>(decode_pdu(kept("11 0C"), Role::kRequest)));
  const auto r = as<CommEventLogResponse>(
      decode_pdu(kept("11 0C 08 00 00 01 08 01 21 20 00"), Role::kResponse));
  EXPECT_EQ(r.byte_count, 8);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.event_count, 0x0108);
  EXPECT_EQ(r.message_count, 0x0121);
  EXPECT_EQ(bytes(r.events), (std::vector<unsigned>{0x20, 0x00}));
  EXPECT_TRUE(r.issues.empty());
}

TEST(PduDecode, WriteMultipleCoils) {
  const auto q =
      as<WriteMultipleCoilsRequest>(decode_pdu(kept("11 0F 00 13 00 0A 02 CD 01"), Role::kRequest));
  EXPECT_EQ(q.addr, 0x13);
  EXPECT_EQ(q.qty, 10);
  EXPECT_EQ(q.byte_count, 2);
  EXPECT_EQ(bits(q.coils), (std::vector<int>{1, 0, 1, 1, 0, 0, 1, 1, 1, 0}));
  EXPECT_TRUE(q.issues.empty());
  const auto r = as<WriteMultipleResponse>(decode_pdu(kept("11 0F 00 13 00 0A"), Role::kResponse));
  EXPECT_EQ(r.addr, 0x13);
  EXPECT_EQ(r.qty, 10);
}

TEST(PduDecode, WriteMultipleRegisters) {
  const auto q = as<WriteMultipleRegistersRequest>(
      decode_pdu(kept("11 10 00 01 00 02 04 00 0A 01 02"), Role::kRequest));
  EXPECT_EQ(q.addr, 1);
  EXPECT_EQ(q.qty, 2);
  EXPECT_EQ(q.byte_count, 4);
  EXPECT_EQ(words(q.values), (std::vector<unsigned>{0x000A, 0x0102}));
  const auto r = as<WriteMultipleResponse>(decode_pdu(kept("11 10 00 01 00 02"), Role::kResponse));
  EXPECT_EQ(r.addr, 1);
  EXPECT_EQ(r.qty, 2);
}

TEST(PduDecode, ReportServerId) {
  EXPECT_TRUE(std::holds_alternative<NoDataRequest>(decode_pdu(kept("11 11"), Role::kRequest)));
  const auto r = as<ServerIdResponse>(decode_pdu(kept("11 11 03 2A FF 01"), Role::kResponse));
  EXPECT_EQ(r.byte_count, 3);
  EXPECT_EQ(bytes(r.payload), (std::vector<unsigned>{0x2A, 0xFF, 0x01}));
}

TEST(PduDecode, ReadFileRecord) {
  const auto q = as<FileRecordRequest>(
      decode_pdu(kept("11 14 0E 06 00 04 00 01 00 02 06 00 03 00 09 00 02"), Role::kRequest));
  EXPECT_EQ(q.byte_count, 0x0E);
  ASSERT_EQ(q.records.count(), 2U);
  auto it = q.records.begin();
  EXPECT_EQ(it->ref_type, 6);
  EXPECT_EQ(it->file, 4);
  EXPECT_EQ(it->record, 1);
  EXPECT_EQ(it->record_length, 2);
  ++it;
  EXPECT_EQ(it->file, 3);
  EXPECT_EQ(it->record, 9);
  EXPECT_TRUE(q.issues.empty());

  const auto r = as<ReadFileRecordResponse>(
      decode_pdu(kept("11 14 0C 05 06 0D FE 00 20 05 06 33 CD 00 40"), Role::kResponse));
  EXPECT_EQ(r.byte_count, 0x0C);
  ASSERT_EQ(r.records.count(), 2U);
  auto ri = r.records.begin();
  EXPECT_EQ(ri->resp_length, 5);
  EXPECT_EQ(words(ri->values), (std::vector<unsigned>{0x0DFE, 0x0020}));
  ++ri;
  EXPECT_EQ(words(ri->values), (std::vector<unsigned>{0x33CD, 0x0040}));
  EXPECT_TRUE(r.issues.empty());
}

TEST(PduDecode, WriteFileRecordBothRoles) {
  const Record f = frame_with_crc("11 15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D");
  for (const Role role : {Role::kRequest, Role::kResponse}) {
    const auto w = as<FileRecordRequest>(decode_pdu(f, role));
    EXPECT_EQ(w.byte_count, 0x0D);
    ASSERT_EQ(w.records.count(), 1U);
    EXPECT_EQ(w.records.begin()->file, 4);
    EXPECT_EQ(w.records.begin()->record, 7);
    EXPECT_EQ(words(w.records.begin()->values), (std::vector<unsigned>{0x06AF, 0x04BE, 0x100D}));
    EXPECT_TRUE(w.issues.empty());
  }
}

TEST(PduDecode, MaskWriteBothRoles) {
  const Record f = frame_with_crc("11 16 00 04 00 F2 00 25");
  for (const Role role : {Role::kRequest, Role::kResponse}) {
    const auto m = as<MaskWrite>(decode_pdu(f, role));
    EXPECT_EQ(m.addr, 4);
    EXPECT_EQ(m.and_mask, 0xF2);
    EXPECT_EQ(m.or_mask, 0x25);
  }
}

TEST(PduDecode, ReadWriteMultipleRegisters) {
  const Record req = frame_with_crc("11 17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF");
  const auto q = as<ReadWriteMultipleRequest>(decode_pdu(req, Role::kRequest));
  EXPECT_EQ(q.read_addr, 3);
  EXPECT_EQ(q.read_qty, 6);
  EXPECT_EQ(q.write_addr, 0x0E);
  EXPECT_EQ(q.write_qty, 3);
  EXPECT_EQ(q.byte_count, 6);
  EXPECT_EQ(words(q.values), (std::vector<unsigned>{0xFF, 0xFF, 0xFF}));
  Record rsp = frame_with_crc("11 17 0C 00 FE 0A CD 00 01 00 03 00 0D 00 FF");
  rsp.request = &req;
  const auto r = as<ReadRegistersResponse>(decode_pdu(rsp, Role::kResponse));
  EXPECT_EQ(r.values.size(), 6U);
  EXPECT_EQ(r.values[1], 0x0ACD);
  EXPECT_EQ(r.addr, 3);  // the read part of the request
  EXPECT_EQ(r.qty, 6);
}

TEST(PduDecode, ReadFifoQueue) {
  EXPECT_EQ(as<FifoRequest>(decode_pdu(kept("11 18 04 DE"), Role::kRequest)).addr, 0x04DE);
  const auto r =
      as<FifoResponse>(decode_pdu(kept("11 18 00 06 00 02 01 B8 12 84"), Role::kResponse));
  EXPECT_EQ(r.byte_count, 6);
  EXPECT_EQ(r.fifo_count, 2);
  EXPECT_EQ(words(r.values), (std::vector<unsigned>{0x01B8, 0x1284}));
  EXPECT_TRUE(r.issues.empty());
}

TEST(PduDecode, ReadDeviceIdentification) {
  const auto q = as<DeviceIdRequest>(decode_pdu(kept("11 2B 0E 01 00"), Role::kRequest));
  EXPECT_EQ(q.mei, 0x0E);
  EXPECT_EQ(q.read_device_id_code, 1);
  EXPECT_EQ(q.object_id, 0);
  // "ACME" / "X1" / "V2.11"
  const auto r = as<DeviceIdResponse>(
      decode_pdu(kept("11 2B 0E 01 01 00 00 03 00 04 41 43 4D 45 01 02 58 31 02 05 56 32 2E 31 31"),
                 Role::kResponse));
  EXPECT_EQ(r.conformity, 1);
  EXPECT_EQ(r.more_follows, 0);
  EXPECT_EQ(r.object_count, 3);
  ASSERT_EQ(r.objects.count(), 3U);
  auto it = r.objects.begin();
  EXPECT_EQ(std::string(it->value.begin(), it->value.end()), "ACME");
  ++it;
  ++it;
  EXPECT_EQ(it->id, 2);
  EXPECT_EQ(std::string(it->value.begin(), it->value.end()), "V2.11");
  EXPECT_TRUE(r.issues.empty());
}

TEST(PduDecode, MeiCanopenStaysRaw) {
  for (const Role role : {Role::kRequest, Role::kResponse}) {
    const auto m = as<MeiPdu>(decode_pdu(kept("11 2B 0D 01 02 03"), role));
    EXPECT_EQ(m.mei, 0x0D);
    EXPECT_EQ(bytes(m.payload), (std::vector<unsigned>{1, 2, 3}));
  }
}

TEST(PduDecode, ExceptionResponse) {
  const Record f = frame_from_hex("01 83 02 C0 F1");  // FORMATS.md §8.3
  ASSERT_TRUE(f.crc_ok);
  for (const Role role : {Role::kResponse, Role::kUnknown}) {
    const auto e = as<ExceptionResponse>(decode_pdu(f, role));
    EXPECT_EQ(e.function, 0x83);
    EXPECT_EQ(e.code, 2);
  }
  // A request never carries the exception bit: it stays raw.
  EXPECT_TRUE(std::holds_alternative<RawPdu>(decode_pdu(f, Role::kRequest)));
}

TEST(PduDecode, UnknownFunctionAndUnknownRoleStayRaw) {
  const Record vendor = frame_with_crc("01 41 01 02 03");
  for (const Role role : {Role::kRequest, Role::kResponse, Role::kUnknown}) {
    const auto r = as<RawPdu>(decode_pdu(vendor, role));
    EXPECT_EQ(bytes(r.data), (std::vector<unsigned>{1, 2, 3}));
  }
  EXPECT_TRUE(
      std::holds_alternative<RawPdu>(decode_pdu(kept("11 03 00 6B 00 03"), Role::kUnknown)));
}

}  // namespace
}  // namespace rtu
