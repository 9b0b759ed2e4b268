// write_pdu_json() and append_pdu_summary(), compared literally.
#include <gtest/gtest.h>

#include <deque>

#include "modbus/pdu.hpp"
#include "pdu_test_support.hpp"

namespace rtu {
namespace {

using test::frame_from_hex;
using test::frame_with_crc;
using test::pdu_json;
using test::pdu_summary;

const Record& kept(Record r) {
  static std::deque<Record> frames;  // decoded views point into their Record
  frames.push_back(r);
  return frames.back();
}

DecodedPdu request(std::string_view hex) {
  return decode_pdu(kept(frame_with_crc(hex)), Role::kRequest);
}

DecodedPdu response(std::string_view hex) {
  return decode_pdu(kept(frame_with_crc(hex)), Role::kResponse);
}

// A response decoded with its request as context.
DecodedPdu answered(std::string_view request_hex, std::string_view response_hex) {
  const Record& req = kept(frame_with_crc(request_hex));
  Record rsp = frame_with_crc(response_hex);
  rsp.request = &req;
  return decode_pdu(kept(rsp), Role::kResponse);
}

// ---- JSON ----------------------------------------------------------------------------

TEST(PduJson, ReadRequestAndResponse) {  // devices/YW2050.md
  EXPECT_EQ(pdu_json(request("01 03 00 32 00 03")), R"({"addr":50,"qty":3})");
  EXPECT_EQ(pdu_json(answered("01 03 00 32 00 03", "01 03 06 EA 60 C3 50 DB 6C")),
            R"({"addr":50,"qty":3,"byte_count":6,"values":[60000,50000,56172]})");
  EXPECT_EQ(pdu_json(response("01 03 06 EA 60 C3 50 DB 6C")),
            R"({"byte_count":6,"values":[60000,50000,56172]})");
}

TEST(PduJson, CoilsTrimmedToTheRequest) {  // devices/YW2300.md
  EXPECT_EQ(pdu_json(answered("01 01 00 00 00 03", "01 01 01 03")),
            R"({"addr":0,"qty":3,"byte_count":1,"coils":[1,1,0]})");
}

TEST(PduJson, WriteSingleCoil) {
  EXPECT_EQ(pdu_json(request("01 05 00 00 FF 00")), R"({"addr":0,"value":65280,"coil":true})");
  EXPECT_EQ(pdu_json(request("01 05 00 01 00 00")), R"({"addr":1,"value":0,"coil":false})");
  EXPECT_EQ(pdu_json(request("01 05 00 01 12 34")), R"({"addr":1,"value":4660,"coil":null})");
  EXPECT_EQ(pdu_json(response("01 06 00 02 00 02")), R"({"addr":2,"value":2})");
}

TEST(PduJson, MalformedWriteMultipleFromYakotec) {  // devices/YAKOTEC.md
  const Record& f =
      kept(frame_from_hex("01 10 00 21 00 05 0C 00 0A 00 64 00 64 00 3C 00 00 00 03 E8 04 76"));
  EXPECT_EQ(pdu_json(decode_pdu(f, Role::kRequest)),
            R"({"addr":33,"qty":5,"byte_count":12,"values":[10,100,100,60,0,3]})");
}

TEST(PduJson, WriteMultipleCoils) {
  EXPECT_EQ(pdu_json(request("11 0F 00 13 00 0A 02 CD 01")),
            R"({"addr":19,"qty":10,"byte_count":2,"coils":[1,0,1,1,0,0,1,1,1,0]})");
  EXPECT_EQ(pdu_json(response("11 0F 00 13 00 0A")), R"({"addr":19,"qty":10})");
}

TEST(PduJson, Exception) {
  EXPECT_EQ(pdu_json(response("01 83 02")),
            R"({"exception":{"code":2,"name":"ILLEGAL DATA ADDRESS"}})");
}

TEST(PduJson, DiagnosticsAndCounters) {
  EXPECT_EQ(pdu_json(request("11 08 00 00 A5 37")),
            R"({"sub_function":0,"sub_function_name":"Return Query Data","data":"a537"})");
  EXPECT_EQ(pdu_json(request("11 07")), "{}");
  EXPECT_EQ(pdu_json(response("11 07 6D")), R"({"status":109})");
  EXPECT_EQ(pdu_json(response("11 0B FF FF 01 08")), R"({"status":65535,"event_count":264})");
  EXPECT_EQ(pdu_json(response("11 0C 08 00 00 01 08 01 21 20 00")),
            R"({"byte_count":8,"status":0,"event_count":264,"message_count":289,"events":"2000"})");
  EXPECT_EQ(pdu_json(response("11 11 03 2A FF 01")), R"({"byte_count":3,"data":"2aff01"})");
}

TEST(PduJson, FileRecords) {
  EXPECT_EQ(pdu_json(request("11 14 0E 06 00 04 00 01 00 02 06 00 03 00 09 00 02")),
            R"({"byte_count":14,"sub_requests":[)"
            R"({"ref_type":6,"file":4,"record":1,"length":2},)"
            R"({"ref_type":6,"file":3,"record":9,"length":2}]})");
  EXPECT_EQ(pdu_json(response("11 14 0C 05 06 0D FE 00 20 05 06 33 CD 00 40")),
            R"({"byte_count":12,"records":[)"
            R"({"length":5,"ref_type":6,"values":[3582,32]},)"
            R"({"length":5,"ref_type":6,"values":[13261,64]}]})");
  EXPECT_EQ(pdu_json(request("11 15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D")),
            R"({"byte_count":13,"records":[)"
            R"({"ref_type":6,"file":4,"record":7,"length":3,"values":[1711,1214,4109]}]})");
}

TEST(PduJson, MaskWriteReadWriteAndFifo) {
  EXPECT_EQ(pdu_json(request("11 16 00 04 00 F2 00 25")),
            R"({"addr":4,"and_mask":242,"or_mask":37})");
  EXPECT_EQ(pdu_json(request("11 17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF")),
            R"({"read_addr":3,"read_qty":6,"write_addr":14,"write_qty":3,"byte_count":6,)"
            R"("values":[255,255,255]})");
  EXPECT_EQ(pdu_json(request("11 18 04 DE")), R"({"addr":1246})");
  EXPECT_EQ(pdu_json(response("11 18 00 06 00 02 01 B8 12 84")),
            R"({"byte_count":6,"fifo_count":2,"values":[440,4740]})");
}

TEST(PduJson, DeviceIdentification) {
  EXPECT_EQ(pdu_json(request("11 2B 0E 01 00")),
            R"({"mei":14,"read_device_id_code":1,"object_id":0})");
  // Objects: VendorName "ACME", a private object 0x80 holding Latin-1 "é" (E9) and a tab.
  EXPECT_EQ(pdu_json(response("11 2B 0E 03 83 FF 80 02 00 04 41 43 4D 45 80 02 E9 09")),
            R"({"mei":14,"read_device_id_code":3,"conformity":131,"more_follows":true,)"
            R"("next_object_id":128,"object_count":2,"objects":[)"
            R"({"id":0,"name":"VendorName","value":"ACME"},)"
            "{\"id\":128,\"name\":null,\"value\":\"\xC3\xA9\\t\"}]}");
  EXPECT_EQ(pdu_json(request("11 2B 0D 01 02")), R"({"mei":13,"data":"0102"})");
}

TEST(PduJson, RawPayload) {
  EXPECT_EQ(pdu_json(request("01 41 01 02 03")), R"({"data":"010203"})");
  EXPECT_EQ(pdu_json(request("01 03 00 32")), R"({"data":"0032"})");  // truncated
}

// ---- summaries -----------------------------------------------------------------------

TEST(PduSummary, Reads) {
  EXPECT_EQ(pdu_summary(request("01 03 00 32 00 03")), "read holding 0x0032 ×3");
  EXPECT_EQ(pdu_summary(response("01 03 06 EA 60 C3 50 DB 6C")), "→ 3 regs 0xEA60 0xC350 0xDB6C");
  EXPECT_EQ(pdu_summary(request("01 01 00 00 00 03")), "read coils 0x0000 ×3");
  EXPECT_EQ(pdu_summary(answered("01 01 00 00 00 03", "01 01 01 03")), "→ 3 coils 110");
  EXPECT_EQ(pdu_summary(answered("01 02 00 00 00 0A", "01 02 02 1F 02")),
            "→ 10 inputs 11111000 01");
  // Long lists are cut after 8 values.
  EXPECT_EQ(pdu_summary(response("01 04 14 00 01 00 02 00 03 00 04 00 05 00 06 00 07 00 08 00 "
                                 "09 00 0A")),
            "→ 10 regs 0x0001 0x0002 0x0003 0x0004 0x0005 0x0006 0x0007 0x0008 …");
}

TEST(PduSummary, Writes) {
  EXPECT_EQ(pdu_summary(request("01 06 00 02 00 02")), "write register 0x0002 = 0x0002");
  EXPECT_EQ(pdu_summary(response("01 06 00 02 00 02")), "→ register 0x0002 = 0x0002");
  EXPECT_EQ(pdu_summary(request("01 05 00 00 FF 00")), "write coil 0x0000 = ON");
  EXPECT_EQ(pdu_summary(response("01 05 00 00 00 00")), "→ coil 0x0000 = OFF");
  EXPECT_EQ(pdu_summary(request("01 05 00 00 12 34")), "write coil 0x0000 = 0x1234 (invalid)");
  EXPECT_EQ(pdu_summary(request("01 10 00 00 00 02 04 00 64 00 00")),
            "write registers 0x0000 ×2 = 0x0064 0x0000");
  EXPECT_EQ(pdu_summary(response("01 10 00 00 00 02")), "→ wrote registers 0x0000 ×2");
  EXPECT_EQ(pdu_summary(request("11 0F 00 13 00 0A 02 CD 01")),
            "write coils 0x0013 ×10 = 10110011 10");
  EXPECT_EQ(pdu_summary(response("11 0F 00 13 00 0A")), "→ wrote coils 0x0013 ×10");
  EXPECT_EQ(pdu_summary(request("11 16 00 04 00 F2 00 25")),
            "mask write 0x0004 and 0x00F2 or 0x0025");
  EXPECT_EQ(pdu_summary(request("11 17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF")),
            "read 0x0003 ×6 write 0x000E ×3 = 0x00FF 0x00FF 0x00FF");
}

TEST(PduSummary, ExceptionsAndSerialLineFunctions) {
  EXPECT_EQ(pdu_summary(response("01 83 02")), "exception 02 ILLEGAL DATA ADDRESS");
  EXPECT_EQ(pdu_summary(request("11 07")), "read exc status");
  EXPECT_EQ(pdu_summary(response("11 07 6D")), "→ status 0x6D");
  EXPECT_EQ(pdu_summary(request("11 08 00 00 A5 37")), "diagnostics 00 Return Query Data A5 37");
  EXPECT_EQ(pdu_summary(response("11 08 00 0B 01 2C")), "→ 0B Return Bus Message Count 01 2C");
  EXPECT_EQ(pdu_summary(response("11 0B FF FF 01 08")), "→ status 0xFFFF events 264");
  EXPECT_EQ(pdu_summary(response("11 0C 08 00 00 01 08 01 21 20 00")),
            "→ status 0x0000 events 264 messages 289 log 20 00");
  EXPECT_EQ(pdu_summary(response("11 11 03 2A FF 01")), "→ 3 bytes 2A FF 01");
}

TEST(PduSummary, FilesFifoAndDeviceId) {
  EXPECT_EQ(pdu_summary(request("11 14 0E 06 00 04 00 01 00 02 06 00 03 00 09 00 02")),
            "read file #4 rec 1 ×2, #3 rec 9 ×2");
  EXPECT_EQ(pdu_summary(response("11 14 0C 05 06 0D FE 00 20 05 06 33 CD 00 40")),
            "→ 2 records: 2 regs, 2 regs");
  EXPECT_EQ(pdu_summary(response("11 15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D")),
            "→ wrote #4 rec 7 ×3");
  EXPECT_EQ(pdu_summary(request("11 18 04 DE")), "read fifo 0x04DE");
  EXPECT_EQ(pdu_summary(response("11 18 00 06 00 02 01 B8 12 84")), "→ 2 values 0x01B8 0x1284");
  EXPECT_EQ(pdu_summary(request("11 2B 0E 01 00")), "read device id basic from 0x00");
  EXPECT_EQ(pdu_summary(response("11 2B 0E 03 83 FF 80 02 00 04 41 43 4D 45 80 02 E9 09")),
            R"(→ conformity 0x83 more from 0x80 VendorName="ACME", 0x80="..")");
}

TEST(PduSummary, RawAndTruncated) {
  EXPECT_EQ(pdu_summary(request("01 41 01 02 03")), "user fc 0x41 3 bytes 01 02 03");
  EXPECT_EQ(pdu_summary(request("01 5A")), "unknown fc 0x5A");
  EXPECT_EQ(pdu_summary(request("01 03 00 32")), "read holding (truncated) 2 bytes 00 32");
  EXPECT_EQ(pdu_summary(request("11 2B 0D 01 02")), "mei 0x0D 2 bytes 01 02");
}

}  // namespace
}  // namespace rtu
