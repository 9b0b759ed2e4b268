#include "capture/stamp_shape_scanner.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <string_view>

#include "capture/plain_seconds.hpp"

namespace rtu {
namespace {

// What both scans say of one text.
struct Scan {
  std::size_t length = 0;
  Nanos ns = -1;
  int decimals = -1;
};

// The text in a heap block of exactly its size, so that a read past its end is one that the
// address sanitizer sees (a short std::string keeps its characters inside itself).
class ExactText {
 public:
  explicit ExactText(const std::string& text)
      : size_(text.size()), chars_(std::make_unique<char[]>(text.size())) {
    if (size_ > 0) std::memcpy(chars_.get(), text.data(), size_);
  }
  [[nodiscard]] std::string_view view() const { return {chars_.get(), size_}; }

 private:
  std::size_t size_;
  std::unique_ptr<char[]> chars_;
};

Scan scan_general(std::string_view text) {
  Scan s;
  s.length = scan_plain_seconds(text, s.ns, s.decimals);
  return s;
}

Scan scan_shaped(StampShapeScanner& scanner, std::string_view text) {
  Scan s;
  s.length = scanner.scan(text, s.ns, s.decimals);
  return s;
}

TEST(StampShapeScanner, ReadsLinesOfOneShapeAsTheGeneralScanDoes) {
  StampShapeScanner scanner;
  // A per-byte capture's lines, then one whose whole seconds change, then an epoch stamp.
  for (const char* line : {"0.000572916 01\n0.001145832 03\n", "0.001145832 03\n0.1\n",
                           "0.999999999 ff\n1.000572916 01\n", "1.000572916 01\n1.00057291 x",
                           "1700000000.123456 01 03\n", "1700000000.123457 01 03\n",
                           "1700000001.000000 01 03\n", "1700000001.0000001 01 03\n"}) {
    const ExactText text{std::string(line)};
    const Scan general = scan_general(text.view());
    const Scan shaped = scan_shaped(scanner, text.view());
    EXPECT_EQ(shaped.length, general.length) << line;
    EXPECT_EQ(shaped.ns, general.ns) << line;
    EXPECT_EQ(shaped.decimals, general.decimals) << line;
  }
}

// Random stamps, most of them in the shape of the one before (same whole seconds, same
// number of decimals) as in a capture, the rest anything: other whole seconds or decimals,
// a non-digit among them, too many digits, values past int64 ns, text that ends early. The
// scanner must answer each exactly as the general scan does, and leave its outputs alone
// where that scan reads nothing.
TEST(StampShapeScanner, AgreesWithTheGeneralScanOnRandomStamps) {
  std::mt19937 random(11);
  const auto pick = [&random](std::size_t n) { return static_cast<std::size_t>(random() % n); };
  const auto digits = [&](std::size_t n) {
    std::string s;
    for (std::size_t i = 0; i < n; ++i) s += static_cast<char>('0' + pick(10));
    return s;
  };
  const std::string_view noise =
      " \t#.x/:\n\xb9\xff"
      "0123456789";
  StampShapeScanner scanner;
  std::string whole = "0";
  std::size_t decimals = 9;
  std::size_t in_shape = 0;
  for (int n = 0; n < 300000; ++n) {
    const std::size_t change = pick(20);
    if (change == 0) whole = digits(pick(12));
    if (change == 1) decimals = pick(11);
    if (change == 2) whole = "92233720" + digits(pick(3));  // near and past int64 ns
    std::string stamp = whole + "." + digits(decimals);
    if (change == 3) stamp[pick(stamp.size())] = noise[pick(noise.size())];
    if (change == 4) stamp = whole;  // no point at all
    // What follows the stamp: a line's rest, sometimes cut short or absent.
    std::string rest;
    if (pick(8) == 0) {
      rest.push_back(noise[pick(noise.size())]);
    } else {
      rest.append(" 01\n");
    }
    rest.append(pick(4) == 0 ? pick(6) : 16, 'a');
    rest.resize(pick(10) == 0 ? pick(rest.size() + 1) : rest.size());
    stamp.append(rest);
    const ExactText text{stamp};
    const Scan general = scan_general(text.view());
    const Scan shaped = scan_shaped(scanner, text.view());
    ASSERT_EQ(shaped.length, general.length) << text.view();
    ASSERT_EQ(shaped.ns, general.ns) << text.view();
    ASSERT_EQ(shaped.decimals, general.decimals) << text.view();
    if (general.length > 0 && change > 4) ++in_shape;
  }
  EXPECT_GT(in_shape, 100000U);  // most stamps came in the shape before them
}

}  // namespace
}  // namespace rtu
