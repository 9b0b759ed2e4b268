// Every example frame of the four device manuals (transcribed in the shared device notes)
// decodes to the values the manual states, through the bundled maps in dissectors/.
#include <gtest/gtest.h>

#include "dissect_test_support.hpp"

namespace rtu::dissect::testing {
namespace {

TEST(DissectTh900, ReadSvGives70Point0AndAZeroSpareRegister) {
  Bus bus("th900");
  const Decoded d = bus.exchange("01 03 00 00 00 02 C4 0B", "01 03 04 02 BC 00 00 3A 6F");
  EXPECT_TRUE(bus.last_request().crc_ok);
  const auto* sv = find_point(d, "SV");
  ASSERT_NE(sv, nullptr);
  EXPECT_EQ(sv->raw, 0x02BCU);
  EXPECT_DOUBLE_EQ(sv->value, 70.0);
  ASSERT_EQ(d.points.size(), 2U);
  EXPECT_EQ(d.points[1].spare_index, 1);
  EXPECT_EQ(d.points[1].raw, 0U);
  EXPECT_TRUE(bus.issues().empty());
  EXPECT_EQ(bus.text(), "  SV=70.0  SV+1=0x0000");
  EXPECT_EQ(bus.json(),
            R"({"device":"th900","registers":[{"addr":0,"name":"SV","raw":700,"value":70.0,)"
            R"("unit":null},{"addr":1,"name":"SV+1","raw":0,"value":null,"unit":null}]})");
}

TEST(DissectTh900, NonZeroSpareRegisterIsFlaggedNotInterpreted) {
  Bus bus("th900");
  bus.request_hex("01 03 00 00 00 02 C4 0B");
  const Decoded d = bus.response(made_frame("01 03 04 02 BC 00 01", Role::kResponse, 9));
  EXPECT_DOUBLE_EQ(find_point(d, "SV")->value, 70.0);
  EXPECT_TRUE(bus.issues().has(IssueId::kReservedNonzero));
}

TEST(DissectTh900, WriteSv100Point0) {
  Bus bus("th900");
  const Decoded w = bus.request_hex("01 10 00 00 00 02 04 03 E8 00 00 73 DF");
  EXPECT_TRUE(bus.last_request().crc_ok);
  const auto* sv = find_point(w, "SV");
  ASSERT_NE(sv, nullptr);
  EXPECT_DOUBLE_EQ(sv->value, 100.0);
  EXPECT_TRUE(bus.issues().empty());
  const Decoded r = bus.response(frame("01 10 00 00 00 02 41 C8", Role::kResponse, 7));
  EXPECT_TRUE(r.points.empty());
}

TEST(DissectTh900, WriteTo0023IsShownRawAndFlaggedUndefined) {
  // The manual calls this "write CYT = 9" but its own table puts CYT at 2F.
  Bus bus("th900");
  const Decoded w = bus.request_hex("01 06 00 23 00 09 B8 06");
  EXPECT_TRUE(bus.last_request().crc_ok);
  ASSERT_EQ(w.points.size(), 1U);
  EXPECT_EQ(w.points[0].point, nullptr);
  EXPECT_EQ(w.points[0].addr, 0x23U);
  EXPECT_EQ(w.points[0].raw, 9U);
  EXPECT_TRUE(bus.issues().has(IssueId::kUndefinedRegister));
  EXPECT_EQ(bus.request_text(), "  [0x0023]=0x0009");
}

TEST(DissectTh900, GenericExampleReadsUndefinedAddresses) {
  Bus bus("th900");
  bus.request_hex("01 03 00 10 00 02 C5 CE");
  EXPECT_TRUE(bus.last_request().crc_ok);
  EXPECT_TRUE(bus.issues().has(IssueId::kUndefinedRegister));
}

TEST(DissectTh900, WriteToReadOnlyPvIsFlagged) {
  Bus bus("th900");
  bus.request(made_frame("01 06 00 F0 01 00", Role::kRequest, 0));
  EXPECT_TRUE(bus.issues().has(IssueId::kReadOnlyWrite));
}

TEST(DissectTh900, ManualAutoEnum) {
  Bus bus("th900");
  bus.request(made_frame("01 03 00 F5 00 01", Role::kRequest, 0));
  bus.response(made_frame("01 03 02 00 40", Role::kResponse, 1));
  EXPECT_EQ(bus.text(), "  M/A=manual");
}

TEST(DissectYw2050, ReadAt0032WithPtCtUnknownAssumesDefaultsAndSaysSo) {
  Bus bus("yw2050");
  const Decoded d = bus.exchange("01 03 00 32 00 03 A4 04", "01 03 06 EA 60 C3 50 DB 6C D1 3F");
  EXPECT_TRUE(bus.last_request().crc_ok);
  ASSERT_EQ(d.points.size(), 3U);
  const auto* uav = find_point(d, "Uav");
  const auto* iav = find_point(d, "Iav");
  const auto* f = find_point(d, "F");
  ASSERT_TRUE(uav && iav && f);
  EXPECT_EQ(uav->addr, 0x32U);
  EXPECT_EQ(iav->addr, 0x34U);  // byte addressing: register k of the read at 0x32 + 2k
  EXPECT_EQ(f->addr, 0x36U);
  EXPECT_DOUBLE_EQ(uav->value, 600.0);     // 60000 × PT(1, assumed) × 0.01
  EXPECT_DOUBLE_EQ(iav->value, 5.0);       // 50000 × CT(1, assumed) × 0.0001
  EXPECT_NEAR(f->value, 59.999, 0.00001);  // 56172 × 0.00106813 = 59.99900 Hz
  EXPECT_NE(uav->assumed_vars, 0U);
  EXPECT_NE(iav->assumed_vars, 0U);
  EXPECT_EQ(f->assumed_vars, 0U);
  EXPECT_TRUE(bus.issues().has(IssueId::kScaleUnknown));
  EXPECT_EQ(bus.text(), "  Uav=600.00 V (PT=1?)  Iav=5.0000 A (CT=1?)  F=59.999 Hz");
}

TEST(DissectYw2050, WriteMultiplePtIsLearnedOnConfirmationAndScalesVoltages) {
  Bus bus("yw2050");
  const Decoded w = bus.request_hex("01 10 00 00 00 02 04 00 64 00 00 B2 70");
  EXPECT_TRUE(bus.last_request().crc_ok);
  const auto* pt = find_point(w, "PT");
  ASSERT_NE(pt, nullptr);
  EXPECT_DOUBLE_EQ(pt->value, 100.0);  // low word first: 0x0064, 0x0000
  EXPECT_EQ(w.space->id, "write_multiple");
  bus.response(frame("01 10 00 00 00 02 41 C8", Role::kResponse, 50));
  const Decoded d = bus.exchange("01 03 00 32 00 03 A4 04", "01 03 06 EA 60 C3 50 DB 6C D1 3F");
  EXPECT_DOUBLE_EQ(find_point(d, "Uav")->value, 60000.0);
  EXPECT_EQ(find_point(d, "Uav")->assumed_vars, 0U);
  EXPECT_NE(find_point(d, "Iav")->assumed_vars, 0U);  // CT still unknown
  EXPECT_EQ(bus.text(), "  Uav=60000.00 V  Iav=5.0000 A (CT=1?)  F=59.999 Hz");
}

TEST(DissectYw2050, UnconfirmedWriteTeachesNothing) {
  Bus bus("yw2050");
  bus.request_hex("01 10 00 00 00 02 04 00 64 00 00 B2 70");
  bus.response(made_frame("01 90 03", Role::kResponse, 60));  // exception: not written
  const Decoded d = bus.exchange("01 03 00 32 00 03 A4 04", "01 03 06 EA 60 C3 50 DB 6C D1 3F");
  EXPECT_DOUBLE_EQ(find_point(d, "Uav")->value, 600.0);
  EXPECT_NE(find_point(d, "Uav")->assumed_vars, 0U);
}

TEST(DissectYw2050, PtCtReadLowWordFirstAndEnergyLowWordFirst) {
  Bus bus("yw2050");
  // PT = 0x0000_0064 and CT = 0x0000_0032 read from 030E (4 registers, byte addresses).
  bus.request(made_frame("01 03 03 0E 00 04", Role::kRequest, 0));
  Decoded d = bus.response(made_frame("01 03 08 00 64 00 00 00 32 00 00", Role::kResponse, 1));
  ASSERT_NE(find_point(d, "PT"), nullptr);
  EXPECT_DOUBLE_EQ(find_point(d, "PT")->value, 100.0);
  EXPECT_DOUBLE_EQ(find_point(d, "CT")->value, 50.0);
  // +Wh: low word 0x86A0 at 0042, high word 0x0001 at 0044 → 100000 × PT × CT.
  bus.request(made_frame("01 03 00 42 00 02", Role::kRequest, 2));
  d = bus.response(made_frame("01 03 04 86 A0 00 01", Role::kResponse, 3));
  const auto* wh = find_point(d, "+Wh");
  ASSERT_NE(wh, nullptr);
  EXPECT_EQ(wh->raw, 100000U);
  EXPECT_DOUBLE_EQ(wh->value, 100000.0 * 100 * 50);
  EXPECT_FALSE(bus.issues().has(IssueId::kScaleUnknown));
}

TEST(DissectYw2050, WriteSingleWiringUsesTheFc06Space) {
  Bus bus("yw2050");
  const Decoded w = bus.request_hex("01 06 00 02 00 02 A9 CB");
  EXPECT_TRUE(bus.last_request().crc_ok);
  EXPECT_EQ(w.space->id, "write_single");
  const auto* wiring = find_point(w, "wiring");
  ASSERT_NE(wiring, nullptr);
  EXPECT_EQ(bus.request_text(), "  wiring=3P3W");
  // FC06 0000 is the meter's address, not Ua: 0 is outside 1-247.
  bus.request(made_frame("01 06 00 00 00 00", Role::kRequest, 5));
  EXPECT_EQ(bus.request_text(), "  address=0");
  EXPECT_TRUE(bus.issues().has(IssueId::kOutOfRange));
}

TEST(DissectYw2050, SwitchInputsAreOneBytePerAddress) {
  Bus bus("yw2050");
  bus.request(made_frame("01 03 00 58 00 03", Role::kRequest, 0));
  EXPECT_TRUE(bus.issues().has(IssueId::kUndefinedRegister));  // 005D is not mapped
  bus.response(made_frame("01 03 06 81 00 FF 00 01 00", Role::kResponse, 1));
  EXPECT_EQ(bus.text(),
            "  J1-J8=0x81[J1|J8]  J9-J16=0x00  J17-J24=0xFF[J17|J18|J19|J20|J21|J22|J23|J24]"
            "  J25-J32=0x00  J33-J40=0x01[J33]  [0x005D]=0x00");
}

TEST(DissectYw2050, ReadingHalfOfPtIsPartial) {
  Bus bus("yw2050");
  bus.request(made_frame("01 03 03 10 00 01", Role::kRequest, 0));
  EXPECT_TRUE(bus.issues().has(IssueId::kPartialPoint));
  const Decoded d = bus.response(made_frame("01 03 02 00 00", Role::kResponse, 1));
  ASSERT_EQ(d.points.size(), 1U);
  EXPECT_TRUE(d.points[0].partial);
  EXPECT_EQ(bus.text(), "  PT=0x0000(part)");
}

TEST(DissectYw2300, ReadOutputsAndInputs) {
  Bus bus("yw2300");
  Decoded d = bus.exchange("01 01 00 00 00 03 7C 0B", "01 01 01 03 11 89");
  EXPECT_TRUE(bus.last_request().crc_ok);
  ASSERT_EQ(d.points.size(), 3U);
  EXPECT_EQ(bus.text(), "  OUT1=on  OUT2=on  OUT3=off");
  d = bus.exchange("01 02 00 00 00 07 39 C8", "01 02 01 1F E0 40");
  EXPECT_TRUE(bus.last_request().crc_ok);
  EXPECT_EQ(bus.text(), "  DI1=on  DI2=on  DI3=on  DI4=on  DI5=on  DI6=off  DI7=off");
}

TEST(DissectYw2300, ReadPhaseCurrents) {
  Bus bus("yw2300");
  const Decoded d = bus.exchange("01 03 01 06 00 03 E4 36", "01 03 06 13 88 13 88 13 88 4A 31");
  EXPECT_TRUE(bus.last_request().crc_ok);
  for (const char* name : {"IA", "IB", "IC"}) {
    ASSERT_NE(find_point(d, name), nullptr) << name;
    EXPECT_EQ(find_point(d, name)->raw, 5000U) << name;
  }
  EXPECT_TRUE(bus.issues().empty());
}

TEST(DissectYw2300, WriteCoilBaudAndParameters) {
  Bus bus("yw2300");
  Decoded w = bus.request_hex("01 05 00 00 FF 00 8C 3A");
  EXPECT_TRUE(bus.last_request().crc_ok);
  EXPECT_EQ(bus.request_text(), "  OUT1=on");
  w = bus.request_hex("01 06 54 51 00 03 88 2A");
  EXPECT_TRUE(bus.last_request().crc_ok);
  EXPECT_EQ(bus.request_text(), "  baud=9600");
  w = bus.request_hex("01 10 54 50 00 02 04 00 01 00 03 29 91");
  EXPECT_TRUE(bus.last_request().crc_ok);
  EXPECT_EQ(bus.request_text(), "  addr=1  baud=9600");
  EXPECT_TRUE(bus.issues().empty());
}

TEST(DissectYw2300, OvtfProtectionBits) {
  Bus bus("yw2300");
  bus.request(made_frame("01 06 54 5A 80 05", Role::kRequest, 0));
  EXPECT_EQ(bus.request_text(), "  OVTF=0x8005[BIT0|BIT2|BIT15]");
}

TEST(DissectYw2300, InvalidCoilValueIsFlagged) {
  Bus bus("yw2300");
  bus.request(made_frame("01 05 00 01 12 34", Role::kRequest, 0));
  EXPECT_TRUE(bus.issues().has(IssueId::kBadValue));
}

TEST(DissectYakotec, ReadMaxSpeed60) {
  Bus bus("yakotec");
  const Decoded d = bus.exchange("01 03 00 23 00 01 75 C0", "01 03 02 00 3C B8 55");
  EXPECT_TRUE(bus.last_request().crc_ok);
  EXPECT_DOUBLE_EQ(find_point(d, "max_speed")->value, 60.0);
  EXPECT_EQ(bus.text(), "  max_speed=60 r/min");
}

TEST(DissectYakotec, ReadStatusHighWordFirst) {
  Bus bus("yakotec");
  const Decoded d = bus.exchange("01 03 00 0A 00 03 25 C9", "01 03 06 00 00 13 88 00 00 A5 DB");
  EXPECT_TRUE(bus.last_request().crc_ok);
  EXPECT_DOUBLE_EQ(find_point(d, "position")->value, 5000.0);
  EXPECT_DOUBLE_EQ(find_point(d, "status_0C")->value, 0.0);
}

TEST(DissectYakotec, WritesOfSpeedTimesPulsesJogAndControl) {
  Bus bus("yakotec");
  bus.request_hex("01 06 00 23 00 3C 78 11");
  EXPECT_EQ(bus.request_text(), "  max_speed=60 r/min");
  bus.request_hex("01 06 00 21 01 F4 D9 D7");
  EXPECT_EQ(bus.request_text(), "  accel=500 ms");
  const Decoded p = bus.request_hex("01 10 00 24 00 02 04 00 00 13 88 FD 12");
  EXPECT_DOUBLE_EQ(find_point(p, "pulses")->value, 5000.0);  // high word first
  bus.response(frame("01 10 00 24 00 02 01 C3", Role::kResponse, 90));
  bus.request_hex("01 10 00 1D 00 03 06 00 3C 00 64 00 64 66 DE");
  EXPECT_EQ(bus.request_text(), "  jog_speed=60 r/min  jog_accel=100 ms  jog_decel=100 ms");
  bus.request_hex("01 06 00 27 00 01 F8 01");
  EXPECT_EQ(bus.request_text(), "  control=0x0001[dir]");
  bus.request_hex("01 06 00 27 00 02 B8 00");
  EXPECT_EQ(bus.request_text(), "  control=0x0002[jog]");
  EXPECT_TRUE(bus.issues().empty());
}

TEST(DissectYakotec, VendorExceptionTableReplacesStandardNames) {
  Bus bus("yakotec");
  const struct {
    const char* request;
    const char* response;
    std::uint8_t code;
    const char* name;
  } cases[] = {
      {"01 03 00 20 00 01 85 C1", "01 83 01 80 F0", 1, "CRC error"},
      {"01 02 00 00 00 04 79 C9", "01 82 02 C1 61", 2,
       "unsupported function code (only 03, 06, 10)"},
      {"01 03 00 3C 00 01 44 06", "01 83 03 01 31", 3, "register address out of range"},
      {"01 06 FF 00 FF FF B8 6E", "01 86 04 43 A3", 4, "write address out of range"},
      {"01 03 00 20 00 20 45 D8", "01 83 05 81 33", 5, "too many registers in one request"},
      {"01 06 00 00 00 01 48 0A", "01 86 06 C2 62", 6,
       "function code does not fit the address (e.g. write to read-only)"},
      {"01 06 00 20 FF FF 89 B0", "01 86 07 03 A2", 7, "value out of range"},
  };
  for (const auto& c : cases) {
    bus.request_hex(c.request);
    const Record resp = frame(c.response, Role::kResponse, bus.next_seq());
    EXPECT_TRUE(resp.crc_ok) << c.response;
    EXPECT_EQ(resp.storage[2], c.code);
    EXPECT_EQ(bus.table().exception_name(resp.slave(), c.code), c.name);
  }
}

TEST(DissectYakotec, ExceptionExamplesRequestsAreFlaggedWhereTheMapSeesWhy) {
  Bus bus("yakotec");
  bus.request_hex("01 03 00 20 00 01 85 C1");  // bad CRC: not decoded
  EXPECT_FALSE(bus.last_request().crc_ok);
  EXPECT_TRUE(bus.issues().empty());
  bus.request_hex("01 02 00 00 00 04 79 C9");
  EXPECT_TRUE(bus.issues().has(IssueId::kUnsupportedFunction));
  bus.request_hex("01 03 00 3C 00 01 44 06");
  EXPECT_TRUE(bus.issues().has(IssueId::kUndefinedRegister));
  bus.request_hex("01 06 FF 00 FF FF B8 6E");
  EXPECT_TRUE(bus.issues().has(IssueId::kUndefinedRegister));
  bus.request_hex("01 03 00 20 00 20 45 D8");
  EXPECT_TRUE(bus.issues().has(IssueId::kUndefinedRegister));
  bus.request_hex("01 06 00 00 00 01 48 0A");
  EXPECT_TRUE(bus.issues().has(IssueId::kUndefinedRegister));
}

TEST(DissectYakotec, MalformedWriteMultipleIsDecodedAsFarAsPossibleAndFlagged) {
  Bus bus("yakotec");
  const Decoded w =
      bus.request_hex("01 10 00 21 00 05 0C 00 0A 00 64 00 64 00 3C 00 00 00 03 E8 04 76");
  EXPECT_TRUE(bus.last_request().crc_ok);
  EXPECT_TRUE(bus.issues().has(IssueId::kByteCount));
  // Quantity 5 from 0021: accel, decel, max_speed and the two words of pulses.
  ASSERT_EQ(w.points.size(), 4U);
  EXPECT_DOUBLE_EQ(find_point(w, "accel")->value, 10.0);
  EXPECT_DOUBLE_EQ(find_point(w, "decel")->value, 100.0);
  EXPECT_DOUBLE_EQ(find_point(w, "max_speed")->value, 100.0);
  EXPECT_EQ(find_point(w, "pulses")->raw, 0x003C0000U);
  const Decoded r = bus.response(frame("01 10 00 21 00 05 50 00", Role::kResponse, 99));
  EXPECT_TRUE(r.points.empty());
}

}  // namespace
}  // namespace rtu::dissect::testing
