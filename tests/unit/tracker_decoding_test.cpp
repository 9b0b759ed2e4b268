// The tracker hands its decoding of each frame on with the record (Record::pdu), so that
// the stages after it need not decode the frame again. What it hands on must be exactly what
// those stages would have decoded themselves: decode_pdu(record, role), a response with its
// request as context. Checked record by record on every bundled capture, while each record
// passes (the decoding is valid only then).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <string>

#include "capture/open_capture.hpp"
#include "capture_test_files.hpp"
#include "core/json_writer.hpp"
#include "modbus/data_access.hpp"
#include "modbus/pdu.hpp"
#include "pipeline/replay.hpp"

namespace rtu {
namespace {

// Everything a decoding says, as text: its JSON fields and its summary.
std::string described(const DecodedPdu& pdu) {
  fmt::memory_buffer fields;
  JsonWriter json(fields);
  json.begin_object();
  write_pdu_json(json, pdu);
  json.end_object();
  fmt::memory_buffer summary;
  append_pdu_summary(summary, pdu);
  return fmt::format("{} | {}", fmt::to_string(fields), fmt::to_string(summary));
}

// What a data access says, as text: its blocks, their values and its issues.
std::string described(const DataAccess& access) {
  std::string text = fmt::format("issues {}", access.issues.bits());
  for (const DataBlock& b : access) {
    text += fmt::format(" [{} {} {} w{} v{} f{} x{}:", static_cast<int>(b.table), b.addr, b.qty,
                        b.write, b.has_values, b.count_fits, b.invalid_value);
    for (std::size_t i = 0; i < b.words.size(); ++i) text += fmt::format(" {}", b.words[i]);
    for (std::size_t i = 0; i < b.bits.size(); ++i) text += b.bits[i] ? " 1" : " 0";
    text += "]";
  }
  return text;
}

class DecodingCheck final : public RecordSink {
 public:
  explicit DecodingCheck(std::string capture) : capture_(std::move(capture)) {}

  void on_record(Record& record) override {
    if (record.kind != RecordKind::kFrame) {
      EXPECT_EQ(record.pdu, nullptr) << where(record);
      return;
    }
    // Made wherever the tracker decodes for the stages after it: a CRC-valid request that
    // waits for its answer, and a CRC-valid answer.
    if (record.crc_ok && record.role == Role::kResponse && record.request != nullptr) {
      EXPECT_NE(record.pdu, nullptr) << where(record);
    }
    if (record.pdu != nullptr) {
      ++handed_on;
      EXPECT_TRUE(record.crc_ok) << where(record);
      EXPECT_NE(record.role, Role::kUnknown) << where(record);
      EXPECT_EQ(described(record.pdu->pdu), described(decode_pdu(record, record.role)))
          << where(record);
    }
    if (record.request != nullptr) {
      const Record& request = *record.request;
      if (request.pdu != nullptr) {
        ++requests_handed_on;
        EXPECT_EQ(described(request.pdu->pdu), described(decode_pdu(request, Role::kRequest)))
            << where(record);
      }
      // The data access built from the handed-on decodings is the one decoding gives.
      Record request_alone;  // a copy carries no decoding (copy_in_use)
      request_alone.copy_in_use(request);
      Record response_alone;
      response_alone.copy_in_use(record);
      response_alone.request = &request_alone;
      EXPECT_EQ(request_alone.pdu, nullptr);
      EXPECT_EQ(described(data_access(request, &record)),
                described(data_access(request_alone, &response_alone)))
          << where(record);
    }
  }

  int handed_on = 0;
  int requests_handed_on = 0;

 private:
  [[nodiscard]] std::string where(const Record& record) const {
    return fmt::format("{}: record at {}", capture_, record.origin);
  }
  std::string capture_;
};

TEST(TrackerDecoding, EqualsWhatEachStageWouldDecodeForEveryBundledCapture) {
  const auto paths = testing::bundled_text_captures();
  int handed_on = 0;
  int requests_handed_on = 0;
  for (const auto& path : paths) {
    const CaptureOpener open = [&path](WarningSink warnings) {
      return open_capture(path, std::move(warnings));
    };
    const ReplayOptions options;
    const CaptureSurvey survey = survey_capture(open, options);
    DecodingCheck check(path);
    decode_capture(open, survey, options, check);
    handed_on += check.handed_on;
    requests_handed_on += check.requests_handed_on;
  }
  EXPECT_GE(paths.size(), 10U);
  // Hundreds of each, or the check above checked nothing.
  EXPECT_GT(handed_on, 500);
  EXPECT_GT(requests_handed_on, 200);
}

}  // namespace
}  // namespace rtu
