// check_pdu() and check_response_fits(): each rule fires on a crafted frame and stays
// quiet on a good one.
#include <gtest/gtest.h>

#include <deque>

#include "modbus/pdu.hpp"
#include "pdu_test_support.hpp"

namespace rtu {
namespace {

using test::frame_with_crc;

const Record& kept(std::string_view address_and_pdu_hex) {
  static std::deque<Record> frames;  // decoded views point into their Record
  frames.push_back(frame_with_crc(address_and_pdu_hex));
  return frames.back();
}

IssueSet request_issues(std::string_view hex) {
  return check_pdu(decode_pdu(kept(hex), Role::kRequest));
}

IssueSet response_issues(std::string_view hex) {
  return check_pdu(decode_pdu(kept(hex), Role::kResponse));
}

IssueSet fit_issues(std::string_view request_hex, std::string_view response_hex) {
  const Record& request = kept(request_hex);
  Record response = kept(response_hex);
  response.request = &request;
  return check_response_fits(request, response);
}

// Exactly one issue, `id`.
::testing::AssertionResult only(IssueSet issues, IssueId id) {
  IssueSet expected;
  expected.add(id);
  if (issues.bits() == expected.bits()) return ::testing::AssertionSuccess();
  auto failure = ::testing::AssertionFailure() << "expected only " << issue_info(id).key << ", got";
  issues.for_each([&failure](IssueId got) { failure << ' ' << issue_info(got).key; });
  return failure;
}

TEST(PduCheck, GoodFramesOfEveryFunctionAreQuiet) {
  for (const auto* hex : {"11 01 00 13 00 13",
                          "11 02 00 C4 00 16",
                          "11 03 00 6B 00 03",
                          "11 04 00 08 00 01",
                          "11 05 00 AC FF 00",
                          "11 06 00 01 00 03",
                          "11 07",
                          "11 08 00 00 A5 37",
                          "11 0B",
                          "11 0C",
                          "11 0F 00 13 00 0A 02 CD 01",
                          "11 10 00 01 00 02 04 00 0A 01 02",
                          "11 11",
                          "11 14 0E 06 00 04 00 01 00 02 06 00 03 00 09 00 02",
                          "11 15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D",
                          "11 16 00 04 00 F2 00 25",
                          "11 17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF",
                          "11 18 04 DE",
                          "11 2B 0E 01 00",
                          "11 2B 0D 01 02"}) {
    EXPECT_TRUE(request_issues(hex).empty()) << hex;
  }
  for (const auto* hex : {"11 01 03 CD 6B 05",
                          "11 02 03 AC DB 35",
                          "11 03 06 02 2B 00 00 00 64",
                          "11 04 02 00 0A",
                          "11 05 00 AC FF 00",
                          "11 06 00 01 00 03",
                          "11 07 6D",
                          "11 08 00 00 A5 37",
                          "11 0B FF FF 01 08",
                          "11 0C 08 00 00 01 08 01 21 20 00",
                          "11 0F 00 13 00 0A",
                          "11 10 00 01 00 02",
                          "11 11 03 2A FF 01",
                          "11 14 0C 05 06 0D FE 00 20 05 06 33 CD 00 40",
                          "11 15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D",
                          "11 16 00 04 00 F2 00 25",
                          "11 17 0C 00 FE 0A CD 00 01 00 03 00 0D 00 FF",
                          "11 18 00 06 00 02 01 B8 12 84",
                          "11 2B 0E 01 01 00 00 01 00 02 41 42",
                          "11 83 02",
                          "11 C1 01"}) {
    EXPECT_TRUE(response_issues(hex).empty()) << hex;
  }
}

TEST(PduCheck, QuantityRanges) {
  EXPECT_TRUE(only(request_issues("01 03 00 00 00 00"), IssueId::kBadQuantity));
  EXPECT_TRUE(only(request_issues("01 03 00 00 00 7E"), IssueId::kBadQuantity));  // 126
  EXPECT_TRUE(request_issues("01 03 00 00 00 7D").empty());                       // 125
  EXPECT_TRUE(only(request_issues("01 01 00 00 07 D1"), IssueId::kBadQuantity));  // 2001
  EXPECT_TRUE(request_issues("01 02 00 00 07 D0").empty());                       // 2000
  EXPECT_TRUE(only(request_issues("01 04 00 00 07 D0"), IssueId::kBadQuantity));  // 2000 regs
  // FC16 quantity 0 (with the matching byte count 0); 124 cannot fit a 256-byte frame.
  EXPECT_TRUE(only(request_issues("01 10 00 00 00 00 00"), IssueId::kBadQuantity));
  EXPECT_TRUE(only(response_issues("01 10 00 00 00 7C"), IssueId::kBadQuantity));
  EXPECT_TRUE(only(response_issues("01 0F 00 00 07 B1"), IssueId::kBadQuantity));  // 1969
  EXPECT_TRUE(response_issues("01 0F 00 00 07 B0").empty());                       // 1968
  // FC23: read 126; write 0.
  EXPECT_TRUE(
      only(request_issues("01 17 00 00 00 7E 00 00 00 01 02 00 00"), IssueId::kBadQuantity));
  EXPECT_TRUE(only(request_issues("01 17 00 00 00 01 00 00 00 00 00"), IssueId::kBadQuantity));
  EXPECT_TRUE(request_issues("01 17 00 00 00 7D 00 00 00 01 02 00 00").empty());
  // FC24: 32 values is one more than a FIFO holds.
  std::string fifo = "01 18 00 42 00 20";
  for (int i = 0; i < 64; ++i) fifo += " 00";
  EXPECT_TRUE(only(response_issues(fifo), IssueId::kBadQuantity));
}

TEST(PduCheck, ByteCounts) {
  // FC16: quantity 2 wants 4 bytes; 6 are announced and present.
  EXPECT_TRUE(only(request_issues("01 10 00 00 00 02 06 00 01 00 02 00 03"), IssueId::kByteCount));
  // FC16: byte count right for the quantity, but only 2 of the 4 bytes present.
  EXPECT_TRUE(only(request_issues("01 10 00 00 00 02 04 00 01"), IssueId::kByteCount));
  // FC15: 10 coils need 2 bytes, not 1.
  EXPECT_TRUE(only(request_issues("01 0F 00 13 00 0A 01 CD"), IssueId::kByteCount));
  // FC03 response: byte count 6, 4 bytes present; odd byte count.
  EXPECT_TRUE(only(response_issues("01 03 06 00 01 00 02"), IssueId::kByteCount));
  EXPECT_TRUE(only(response_issues("01 03 03 00 01 02"), IssueId::kByteCount));
  // FC01 response with byte count 0.
  EXPECT_TRUE(only(response_issues("01 01 00"), IssueId::kByteCount));
  // FC12 response: byte count 5 cannot hold status and both counters.
  EXPECT_TRUE(response_issues("01 0C 05 00 00 01 08 01").has(IssueId::kByteCount));
  // FC24 response: byte count says 4 but the FIFO count says 2 values.
  EXPECT_TRUE(only(response_issues("01 18 00 04 00 02 01 B8"), IssueId::kByteCount));
  // FC20 request: 8 bytes is not a whole number of 7-byte sub-requests.
  EXPECT_TRUE(only(request_issues("01 14 08 06 00 04 00 01 00 02 00"), IssueId::kByteCount));
}

TEST(PduCheck, CoilValue) {
  EXPECT_TRUE(only(request_issues("01 05 00 00 12 34"), IssueId::kBadValue));
  EXPECT_TRUE(only(response_issues("01 05 00 00 00 FF"), IssueId::kBadValue));
  EXPECT_TRUE(request_issues("01 05 00 00 00 00").empty());
  // FC06 has no such rule.
  EXPECT_TRUE(request_issues("01 06 00 00 12 34").empty());
}

TEST(PduCheck, OtherValues) {
  EXPECT_TRUE(only(request_issues("01 08 00 05 00 00"), IssueId::kBadValue));  // reserved sub
  EXPECT_TRUE(only(request_issues("01 08 00 01 12 00"), IssueId::kBadValue));  // restart data
  EXPECT_TRUE(request_issues("01 08 00 01 FF 00").empty());
  EXPECT_TRUE(only(request_issues("01 2B 0E 05 00"), IssueId::kBadValue));  // read code 5
  EXPECT_TRUE(only(request_issues("01 14 07 05 00 04 00 01 00 02"), IssueId::kBadValue));  // ref 5
}

TEST(PduCheck, Truncated) {
  EXPECT_TRUE(only(request_issues("11 03 00 6B"), IssueId::kTruncated));
  EXPECT_TRUE(only(response_issues("11 83"), IssueId::kTruncated));
  EXPECT_TRUE(only(request_issues("11 08 00 0B 01"), IssueId::kTruncated));
  // FC43 response whose last object runs past the frame.
  EXPECT_TRUE(only(response_issues("11 2B 0E 01 01 00 00 01 00 05 41 42"), IssueId::kTruncated));
  // A frame of two bytes has no room for a CRC.
  Record two;
  two.storage[0] = 0x11;
  two.storage[1] = 0x07;
  two.size = 2;
  EXPECT_TRUE(only(check_pdu(decode_pdu(two, Role::kRequest)), IssueId::kTruncated));
}

TEST(PduCheck, ExtraBytes) {
  EXPECT_TRUE(only(request_issues("11 03 00 6B 00 03 00"), IssueId::kExtraBytes));
  EXPECT_TRUE(only(request_issues("11 07 00"), IssueId::kExtraBytes));
  EXPECT_TRUE(only(response_issues("11 83 02 00"), IssueId::kExtraBytes));
  EXPECT_TRUE(only(request_issues("11 08 00 0B 00 00 00"), IssueId::kExtraBytes));
}

TEST(PduCheck, BroadcastRead) {
  EXPECT_TRUE(only(request_issues("00 03 00 00 00 01"), IssueId::kBroadcastRead));
  EXPECT_TRUE(only(request_issues("00 2B 0E 01 00"), IssueId::kBroadcastRead));
  EXPECT_TRUE(only(request_issues("00 08 00 00 12 34"), IssueId::kBroadcastRead));
  EXPECT_TRUE(request_issues("00 06 00 00 00 01").empty());
  EXPECT_TRUE(request_issues("00 10 00 00 00 01 02 00 07").empty());
  EXPECT_TRUE(request_issues("00 08 00 04 00 00").empty());  // force listen only
}

TEST(PduCheck, ReservedAddress) {
  EXPECT_TRUE(only(request_issues("F8 03 00 00 00 01"), IssueId::kReservedAddress));
  EXPECT_TRUE(only(response_issues("FF 06 00 00 00 01"), IssueId::kReservedAddress));
  EXPECT_TRUE(request_issues("F7 03 00 00 00 01").empty());
}

TEST(PduCheck, UnknownFunction) {
  EXPECT_TRUE(only(request_issues("01 41 00 01"), IssueId::kUnknownFunction));  // user-defined
  EXPECT_TRUE(only(request_issues("01 09 00 01"), IssueId::kUnknownFunction));  // reserved
  EXPECT_TRUE(only(response_issues("01 5A"), IssueId::kUnknownFunction));
  EXPECT_TRUE(only(request_issues("01 83 02"), IssueId::kUnknownFunction));     // request, exc bit
  EXPECT_TRUE(only(request_issues("01 2B 0C 00"), IssueId::kUnknownFunction));  // MEI 0C reserved
  EXPECT_TRUE(response_issues("01 C1 01").empty());  // an exception to an unknown function
}

TEST(PduCheckFits, ReadByteCountAgainstQuantity) {
  EXPECT_TRUE(fit_issues("01 03 00 32 00 03", "01 03 06 EA 60 C3 50 DB 6C").empty());
  EXPECT_TRUE(only(fit_issues("01 03 00 32 00 03", "01 03 04 EA 60 C3 50"), IssueId::kByteCount));
  EXPECT_TRUE(only(fit_issues("01 04 00 00 00 01", "01 04 04 00 01 00 02"), IssueId::kByteCount));
  EXPECT_TRUE(fit_issues("11 01 00 13 00 13", "11 01 03 CD 6B 05").empty());
  EXPECT_TRUE(only(fit_issues("11 01 00 13 00 13", "11 01 02 CD 6B"), IssueId::kByteCount));
  EXPECT_TRUE(only(fit_issues("11 02 00 00 00 08", "11 02 02 CD 6B"), IssueId::kByteCount));
  EXPECT_TRUE(only(fit_issues("11 17 00 03 00 06 00 0E 00 01 02 00 FF", "11 17 02 00 FE"),
                   IssueId::kByteCount));
}

TEST(PduCheckFits, Echoes) {
  EXPECT_TRUE(fit_issues("01 06 00 02 00 02", "01 06 00 02 00 02").empty());
  EXPECT_TRUE(only(fit_issues("01 06 00 02 00 02", "01 06 00 02 00 03"), IssueId::kEchoMismatch));
  EXPECT_TRUE(only(fit_issues("01 05 00 00 FF 00", "01 05 00 01 FF 00"), IssueId::kEchoMismatch));
  EXPECT_TRUE(only(fit_issues("01 16 00 04 00 F2 00 25", "01 16 00 04 00 F2 00 26"),
                   IssueId::kEchoMismatch));
  EXPECT_TRUE(only(fit_issues("01 15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D",
                              "01 15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0E"),
                   IssueId::kEchoMismatch));
  // FC08: Return Query Data echoes its data; counters answer other data.
  EXPECT_TRUE(only(fit_issues("01 08 00 00 A5 37", "01 08 00 00 A5 38"), IssueId::kEchoMismatch));
  EXPECT_TRUE(fit_issues("01 08 00 0B 00 00", "01 08 00 0B 01 2C").empty());
  EXPECT_TRUE(only(fit_issues("01 08 00 0B 00 00", "01 08 00 0C 01 2C"), IssueId::kEchoMismatch));
  EXPECT_TRUE(only(fit_issues("01 2B 0E 01 00", "01 2B 0E 02 01 00 00 01 00 01 41"),
                   IssueId::kEchoMismatch));
}

TEST(PduCheckFits, WriteMultipleAddressAndQuantity) {
  EXPECT_TRUE(fit_issues("01 10 00 00 00 02 04 00 64 00 00", "01 10 00 00 00 02").empty());
  EXPECT_TRUE(only(fit_issues("01 10 00 00 00 02 04 00 64 00 00", "01 10 00 01 00 02"),
                   IssueId::kAddressMismatch));
  EXPECT_TRUE(only(fit_issues("01 0F 00 13 00 0A 02 CD 01", "01 0F 00 13 00 09"),
                   IssueId::kAddressMismatch));
}

TEST(PduCheckFits, FileRecordSubResponses) {
  const auto* request = "11 14 0E 06 00 04 00 01 00 02 06 00 03 00 09 00 02";
  EXPECT_TRUE(fit_issues(request, "11 14 0C 05 06 0D FE 00 20 05 06 33 CD 00 40").empty());
  // Second record answered with one register instead of two.
  EXPECT_TRUE(
      only(fit_issues(request, "11 14 0A 05 06 0D FE 00 20 03 06 33 CD"), IssueId::kByteCount));
}

TEST(PduCheckFits, ExceptionsAndOtherFunctionsAreTheCallersConcern) {
  EXPECT_TRUE(fit_issues("01 03 00 32 00 03", "01 83 02").empty());
  EXPECT_TRUE(fit_issues("01 03 00 32 00 03", "01 04 02 00 01").empty());
}

}  // namespace
}  // namespace rtu
