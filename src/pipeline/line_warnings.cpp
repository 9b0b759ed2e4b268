#include "pipeline/line_warnings.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <utility>
#include <vector>

#include "capture/capture_warnings.hpp"

namespace rtu {

std::optional<std::string> assumed_settings_warning(const LineSettings& line, bool declared,
                                                    const LineOverrides& overrides) {
  if (declared) return std::nullopt;  // a file declares all three or none
  std::vector<std::string_view> missing;
  std::vector<std::string> assumed;
  std::vector<std::string_view> options;
  if (!overrides.baud) {
    missing.emplace_back("baud rate");
    assumed.push_back(fmt::format("{} baud", line.baud));
    options.emplace_back("--baud");
  }
  if (!overrides.parity) {
    missing.emplace_back("parity");
    assumed.push_back(fmt::format("parity {}", parity_letter(line.parity)));
    options.emplace_back("--parity");
  }
  if (!overrides.stop_bits) {
    missing.emplace_back("stop bits");
    assumed.push_back(fmt::format("{} stop bit{}", line.stop_bits, line.stop_bits == 1 ? "" : "s"));
    options.emplace_back("--stop");
  }
  if (missing.empty()) return std::nullopt;
  if (missing.size() == 3) {
    return fmt::format(
        "no line settings in the capture or on the command line: assumed {} (Modbus default); "
        "use --baud/--parity/--stop",
        line.describe());
  }
  return fmt::format(
      "no {} in the capture or on the command line: assumed {} (Modbus default), so the line "
      "is {}; use {}",
      fmt::join(missing, " or "), fmt::join(assumed, " and "), line.describe(),
      fmt::join(options, "/"));
}

void add_line_warnings(CaptureInfo& info, bool declared, const LineOverrides& overrides,
                       const LineCheck& check, Nanos precision, bool print) {
  const std::size_t first_new = info.warnings.size();
  if (auto w = assumed_settings_warning(info.line, declared, overrides)) {
    info.warnings.push_back(std::move(*w));
  }
  if (auto w = check.warning(info.line, precision)) info.warnings.push_back(std::move(*w));
  if (!print) return;
  for (std::size_t i = first_new; i < info.warnings.size(); ++i) {
    print_warning_to_stderr(fmt::format("{}: {}", info.source, info.warnings[i]));
  }
}

}  // namespace rtu
