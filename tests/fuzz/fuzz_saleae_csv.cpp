// Fuzz target for the Saleae Logic CSV reader (capture/saleae_reader.hpp), both layouts:
// the input is the file. Oracles (capture_checks.hpp): one byte per chunk with a measured
// start no later than its end, starts never going backwards (the reader clamps them), line
// numbers as origins, and an end or an InputError naming a line.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>

#include "capture/saleae_reader.hpp"
#include "capture_checks.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto& file = rtu::fuzz::fuzz_input_file();
  file.write(data, size);
  rtu::fuzz::CaptureRules rules;
  rules.target = "fuzz_saleae_csv";
  rules.text = std::string_view(reinterpret_cast<const char*>(data), size);
  rules.per_byte_exact = true;
  rules.times_in_order = true;
  rules.origins_are_lines = true;
  (void)rtu::fuzz::read_and_check(
      [&file](rtu::WarningSink warnings) {
        return std::make_unique<rtu::SaleaeReader>(file.path(), std::move(warnings));
      },
      file.path(), rules);
  return 0;
}
