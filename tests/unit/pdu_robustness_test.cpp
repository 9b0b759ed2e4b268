// The decoder on hostile bytes: every prefix of valid frames, and pseudo-random frames of
// every function code, length and role. Run under ASan/UBSan, these show that no byte count
// moves a read outside the frame; the assertions show that damage is always reported.
#include <gtest/gtest.h>

#include <cstdint>

#include "core/crc16.hpp"
#include "modbus/pdu.hpp"
#include "pdu_test_support.hpp"

namespace rtu {
namespace {

using test::frame_with_crc;

void exercise(const Record& frame, Role role) {
  const DecodedPdu pdu = decode_pdu(frame, role);
  (void)check_pdu(pdu);
  (void)test::pdu_json(pdu);
  (void)test::pdu_summary(pdu);
}

// Frames whose every strict prefix breaks a length rule (FC08/00 and MEI 0D excepted: they
// have none).
constexpr const char* kRequests[] = {"11 01 00 13 00 13",
                                     "11 03 00 6B 00 03",
                                     "11 05 00 AC FF 00",
                                     "11 06 00 01 00 03",
                                     "11 08 00 0B 00 00",
                                     "11 0F 00 13 00 0A 02 CD 01",
                                     "11 10 00 01 00 02 04 00 0A 01 02",
                                     "11 14 0E 06 00 04 00 01 00 02 06 00 03 00 09 00 02",
                                     "11 15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D",
                                     "11 16 00 04 00 F2 00 25",
                                     "11 17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF",
                                     "11 18 04 DE",
                                     "11 2B 0E 01 00"};
constexpr const char* kResponses[] = {"11 01 03 CD 6B 05",
                                      "11 03 06 02 2B 00 00 00 64",
                                      "11 07 6D",
                                      "11 0B FF FF 01 08",
                                      "11 0C 08 00 00 01 08 01 21 20 00",
                                      "11 0F 00 13 00 0A",
                                      "11 11 03 2A FF 01",
                                      "11 14 0C 05 06 0D FE 00 20 05 06 33 CD 00 40",
                                      "11 18 00 06 00 02 01 B8 12 84",
                                      "11 2B 0E 01 01 00 00 02 00 02 41 42 01 01 58",
                                      "11 83 02"};

void expect_every_prefix_flagged(const char* hex, Role role) {
  const Record whole = frame_with_crc(hex);
  ASSERT_TRUE(check_pdu(decode_pdu(whole, role)).empty()) << hex;
  for (std::uint16_t n = 0; n < whole.size; ++n) {
    Record cut = whole;
    cut.size = n;  // the last two bytes left are taken as the CRC, as the framer would
    const IssueSet issues = check_pdu(decode_pdu(cut, role));
    EXPECT_TRUE(issues.has(IssueId::kTruncated) || issues.has(IssueId::kByteCount))
        << hex << " cut to " << n << " bytes";
    exercise(cut, role);
  }
}

TEST(PduRobustness, EveryPrefixOfAValidFrameIsFlagged) {
  for (const char* hex : kRequests) expect_every_prefix_flagged(hex, Role::kRequest);
  for (const char* hex : kResponses) expect_every_prefix_flagged(hex, Role::kResponse);
}

TEST(PduRobustness, AnExtraByteIsFlagged) {
  for (const char* hex : kRequests) {
    const Record longer = frame_with_crc(std::string(hex) + " 00");
    const IssueSet issues = check_pdu(decode_pdu(longer, Role::kRequest));
    EXPECT_TRUE(issues.has(IssueId::kExtraBytes) || issues.has(IssueId::kByteCount)) << hex;
  }
}

// Small deterministic generator (xorshift32), so failures reproduce.
class Noise {
 public:
  std::uint8_t next() {
    state_ ^= state_ << 13U;
    state_ ^= state_ >> 17U;
    state_ ^= state_ << 5U;
    return static_cast<std::uint8_t>(state_ >> 24U);
  }

 private:
  std::uint32_t state_ = 0x2545F491U;
};

TEST(PduRobustness, RandomBytesOfEveryFunctionLengthAndRole) {
  Noise noise;
  Record request;
  std::size_t decoded = 0;
  for (unsigned function = 0; function < 256; ++function) {
    for (std::uint16_t size = 0; size <= 40; ++size) {
      Record frame;
      frame.size = size;
      for (std::uint16_t i = 0; i < size; ++i) frame.storage[i] = noise.next();
      if (size > 1) frame.storage[1] = static_cast<std::uint8_t>(function);
      // Byte counts at the usual offsets that claim far more than is there.
      if (size > 6 && (noise.next() & 1U) != 0) frame.storage[2] = 0xFF;
      for (const Role role : {Role::kRequest, Role::kResponse, Role::kUnknown}) {
        exercise(frame, role);
        // The same frame as the request of a response, and as its response.
        frame.request = &request;
        exercise(frame, role);
        (void)check_response_fits(request, frame);
        (void)check_response_fits(frame, request);
        frame.request = nullptr;
        ++decoded;
      }
      request = frame;
    }
  }
  EXPECT_EQ(decoded, 256U * 41U * 3U);
}

TEST(PduRobustness, LongestFrameOfEveryFunction) {
  Noise noise;
  for (unsigned function = 0; function < 256; ++function) {
    Record frame;
    frame.size = kMaxAdu;
    for (auto& b : frame.storage) b = noise.next();
    frame.storage[1] = static_cast<std::uint8_t>(function);
    for (const Role role : {Role::kRequest, Role::kResponse, Role::kUnknown}) {
      exercise(frame, role);
    }
  }
}

}  // namespace
}  // namespace rtu
