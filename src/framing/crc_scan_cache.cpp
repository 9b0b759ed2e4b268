#include "framing/crc_scan_cache.hpp"

#include <algorithm>

namespace rtu {

void extend_side_by_side(std::array<const std::uint8_t*, 4> from, std::array<CrcScan*, 4> scans,
                         std::array<std::size_t, 4> counts) {
  const std::size_t together = *std::min_element(counts.begin(), counts.end());
  CrcScan& s0 = *scans[0];
  CrcScan& s1 = *scans[1];
  CrcScan& s2 = *scans[2];
  CrcScan& s3 = *scans[3];
  std::uint16_t c0 = s0.crc;
  std::uint16_t c1 = s1.crc;
  std::uint16_t c2 = s2.crc;
  std::uint16_t c3 = s3.crc;
  const std::uint8_t* const b0 = from[0];
  const std::uint8_t* const b1 = from[1];
  const std::uint8_t* const b2 = from[2];
  const std::uint8_t* const b3 = from[3];
  for (std::size_t i = 0; i < together; ++i) {
    c0 = crc16_update(c0, b0[i]);
    c1 = crc16_update(c1, b1[i]);
    c2 = crc16_update(c2, b2[i]);
    c3 = crc16_update(c3, b3[i]);
    // A zero is rare (one step in 65,536 on random bytes): one test for the four.
    if (c0 == 0 || c1 == 0 || c2 == 0 || c3 == 0) [[unlikely]] {
      if (c0 == 0 && s0.scanned + i + 1 >= kMinAdu) s0.note_zero(s0.scanned + i + 1);
      if (c1 == 0 && s1.scanned + i + 1 >= kMinAdu) s1.note_zero(s1.scanned + i + 1);
      if (c2 == 0 && s2.scanned + i + 1 >= kMinAdu) s2.note_zero(s2.scanned + i + 1);
      if (c3 == 0 && s3.scanned + i + 1 >= kMinAdu) s3.note_zero(s3.scanned + i + 1);
    }
  }
  const std::array<std::uint16_t, 4> crcs = {c0, c1, c2, c3};
  for (std::size_t k = 0; k < 4; ++k) {
    CrcScan& scan = *scans[k];
    scan.crc = crcs[k];
    scan.scanned = static_cast<std::uint16_t>(scan.scanned + together);
    scan.extend(from[k] + together, counts[k] - together);
  }
}

}  // namespace rtu
