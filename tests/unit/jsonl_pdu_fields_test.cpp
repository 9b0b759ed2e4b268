// The JSONL writer adds the decoded PDU fields to each frame's object, once per key.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "core/output_stream.hpp"
#include "pdu_test_support.hpp"
#include "report/jsonl_writer.hpp"

namespace rtu {
namespace {

std::string write_line(Record& record) {
  const std::string path = ::testing::TempDir() + "jsonl_pdu_fields_test.jsonl";
  {
    OutputStream out(path);
    JsonlWriter writer(out);
    writer.on_record(record);
    writer.on_finish();
  }
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::size_t occurrences(const std::string& text, std::string_view needle) {
  std::size_t n = 0;
  for (auto pos = text.find(needle); pos != std::string::npos; pos = text.find(needle, pos + 1)) {
    ++n;
  }
  return n;
}

TEST(JsonlPduFields, ExceptionObjectIsWrittenOnce) {
  Record frame = test::frame_from_hex("01 83 02 C0 F1");
  frame.role = Role::kResponse;
  const std::string line = write_line(frame);
  EXPECT_EQ(occurrences(line, R"("exception":{"code":2,"name":"ILLEGAL DATA ADDRESS"})"), 1U)
      << line;
}

TEST(JsonlPduFields, DecodedFieldsFollowTheFrameKeys) {
  Record frame = test::frame_from_hex("01 03 00 32 00 03 A4 04");  // devices/YW2050.md
  frame.role = Role::kRequest;
  const std::string line = write_line(frame);
  EXPECT_EQ(occurrences(line, R"("addr":50,"qty":3})"), 1U) << line;
}

}  // namespace
}  // namespace rtu
