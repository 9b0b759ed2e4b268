// Fuzz target for the text hex reader (capture/text_hex_reader.hpp): the input is the file.
// Oracles (capture_checks.hpp): chunks of at least one byte, line numbers as origins, times
// never going backwards (the reader clamps them), and an end or an InputError naming a line;
// also, what it declares from "# baud=..." comments is a usable line.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>

#include "capture/text_hex_reader.hpp"
#include "capture_checks.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto& file = rtu::fuzz::fuzz_input_file();
  file.write(data, size);
  rtu::fuzz::CaptureRules rules;
  rules.target = "fuzz_text_hex";
  rules.text = std::string_view(reinterpret_cast<const char*>(data), size);
  rules.times_in_order = true;
  rules.origins_are_lines = true;
  (void)rtu::fuzz::read_and_check(
      [&file](rtu::WarningSink warnings) {
        return std::make_unique<rtu::TextHexReader>(file.path(), std::move(warnings));
      },
      file.path(), rules);
  return 0;
}
