#include "report/identification_sample.hpp"

#include <fmt/format.h>

namespace rtu {

std::string describe(const IdentificationSample& sample) {
  const std::string noise =
      sample.noise_bytes > 0 ? fmt::format(" and {} bytes of noise", sample.noise_bytes) : "";
  switch (sample.end) {
    case SampleEnd::kEnough:
      return fmt::format(
          "models identified from the first {} frames{} (--identify-frames {}); slaves first "
          "heard later keep raw registers",
          sample.frames, noise, sample.frames_wanted);
    case SampleEnd::kHeldBound:
      return fmt::format(
          "models identified from only the first {} frames{} of {} asked for: the records held "
          "for the decoding meanwhile reached their bound of {} MB (long frames); "
          "--identify-frames 0 looks at the whole capture in a pass of its own",
          sample.frames, noise, sample.frames_wanted, sample.held_bound_bytes / (1024 * 1024));
    case SampleEnd::kCaptureEnd: break;
  }
  return fmt::format("models identified from all {} frames{} of the capture", sample.frames, noise);
}

}  // namespace rtu
