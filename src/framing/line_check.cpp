#include "framing/line_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/bucket_index.hpp"

namespace rtu {
namespace {

// Rates serial equipment is set to; a measured rate close to one of them is that rate. Rare
// rates (128000, 56000, ...) are left out: 128000 at 11 bits a character is 115200 at 10, and
// the common rate is the likelier. Any two of these are a third or more apart, and character
// sizes (10, 11 or 12 bits) only 9% to 20%, so a spacing fits one rate and size at most.
constexpr std::array<std::uint32_t, 16> kStandardBauds = {
    300,   600,   1200,  2400,  4800,   9600,   14400,  19200,
    28800, 38400, 57600, 76800, 115200, 230400, 460800, 921600};

// Enough spacings for a cluster to mean something, and the share of all spacings it must
// hold: back-to-back bytes inside frames are most of them, frame gaps and jitter the rest.
constexpr std::uint64_t kMinCluster = 32;
constexpr std::uint64_t kMinClusterShareDenominator = 4;  // a quarter
// Width of a cluster in buckets: about ±5%, wider than the jitter of a logic analyser's
// sampling or a simulator's rounding, narrower than the step between standard rates.
constexpr std::size_t kClusterBuckets = 7;
// Back-to-back bytes cannot be closer than one character; 10% spares timestamp rounding and
// UART clock tolerance. Spacing of 1.5 characters or more everywhere would mean half a
// character of pause after every byte, which devices rarely do, while 9600-baud traffic
// decoded at 14400 or 19200 shows exactly that.
constexpr double kShortBelow = 0.9;
constexpr double kLongFrom = 1.45;

double millis(Nanos t) {
  return static_cast<double>(t) / 1e6;
}

// What the line likely is: the standard rate the spacing fits at the current character size,
// else at another (8N1 is 10 bits, 8E1/8O1/8N2 11, 8E2/8O2 12), else the measured rate.
struct Likely {
  std::uint32_t baud = 0;
  std::uint32_t bits = 0;
};

double rate_at(Nanos spacing, std::uint32_t bits) {
  return static_cast<double>(bits) * 1e9 / static_cast<double>(spacing);
}

std::optional<Likely> standard_line(Nanos spacing, const LineSettings& line) {
  const std::uint32_t own = line.bits_per_char();
  if (auto baud = nearest_standard_baud(rate_at(spacing, own))) return Likely{*baud, own};
  for (const std::uint32_t bits : {10U, 11U, 12U}) {
    if (bits == own) continue;
    if (auto baud = nearest_standard_baud(rate_at(spacing, bits))) return Likely{*baud, bits};
  }
  return std::nullopt;
}

// The measured rate to three significant digits: more would pretend a precision it lacks.
Likely measured_line(Nanos spacing, const LineSettings& line) {
  const double rate = rate_at(spacing, line.bits_per_char());
  const double step = std::pow(10.0, std::floor(std::log10(rate)) - 2.0);
  return {static_cast<std::uint32_t>(std::llround(rate / step) * static_cast<long long>(step)),
          line.bits_per_char()};
}

// "the line is likely 19200 baud; decode with --baud 19200", naming the character size and
// its options when that differs from the current settings.
std::string likely_text(const Likely& likely, const LineSettings& line) {
  if (likely.bits == line.bits_per_char()) {
    return fmt::format("the line is likely {} baud; decode with --baud {}", likely.baud,
                       likely.baud);
  }
  std::string_view names = "8E1, 8O1 or 8N2";
  std::string_view options = "--parity E --stop 1";
  if (likely.bits == 10) {
    names = "8N1";
    options = "--parity N --stop 1";
  } else if (likely.bits == 12) {
    names = "8E2 or 8O2";
    options = "--parity E --stop 2";
  }
  return fmt::format(
      "the line is likely {} baud with {}-bit characters ({}); decode with --baud {} {}",
      likely.baud, likely.bits, names, likely.baud, options);
}

}  // namespace

std::optional<std::uint32_t> nearest_standard_baud(double rate) {
  std::optional<std::uint32_t> best;
  double best_error = 0.03;
  for (const std::uint32_t baud : kStandardBauds) {
    const double error = std::abs(rate / static_cast<double>(baud) - 1.0);
    if (error <= best_error) {
      best_error = error;
      best = baud;
    }
  }
  return best;
}

std::size_t LineCheck::bucket_by_formula(Nanos spacing) {
  if (spacing < kNanosPerMicro) return 0;
  const double octaves = std::log2(static_cast<double>(spacing) / 1e3);
  const auto b = 1 + static_cast<std::size_t>(static_cast<double>(kPerOctave) * octaves);
  return std::min(b, kBuckets - 1);
}

const BucketIndex& LineCheck::bucket_index() {
  // The formula's buckets, without a logarithm per byte of a per-byte capture.
  static const BucketIndex index(BucketIndex::lower_bounds_of(bucket_by_formula));
  return index;
}

void LineCheck::add(const Chunk& chunk) {
  ++chunks_;
  if (chunk.bytes.size() != 1 || chunk.time_clamped || chunk.read_late) {
    // Several bytes in one read: their spacing is unknown, and so is the next byte's. So is
    // the spacing before and after a time the reader had to clamp, or a read the host made
    // late.
    if (chunk.bytes.size() > 1) ++multi_byte_chunks_;
    last_ = kUnknownTime;
    return;
  }
  // Logic analysers give each byte's start; per-byte reads give its end. Either way the
  // difference between consecutive bytes is their spacing.
  const Nanos t = chunk.t_first_start != kUnknownTime ? chunk.t_first_start : chunk.t_end;
  add_single_bytes(&t, 1);
}

void LineCheck::add(const ByteReads& reads) {
  chunks_ += reads.size();
  add_single_bytes(reads.t_ends, reads.size());
}

void LineCheck::add_single_bytes(const Nanos* times, std::size_t n) {
  // Counted in locals, a run of spacings in one bucket at a time, and stored once the bucket
  // changes: adding each spacing to its bucket in memory made every byte of a per-byte
  // capture wait for the store of the byte before it to the same place.
  const BucketIndex& index = bucket_index();
  // Long silences all land in the top bucket; clamping keeps the sums from overflowing.
  constexpr Nanos kTop = kNanosPerSecond * 4;
  // The range of `bucket`, [from, below): back-to-back bytes repeat one spacing, and
  // finding a bucket takes a look-up.
  std::size_t bucket = bucket_;
  Nanos from = 0;
  Nanos below = 0;
  const auto enter = [&](std::size_t b) {
    bucket = b;
    from = index.lower(b);
    below = b + 1 < index.buckets() ? index.lower(b + 1) : kTop + 1;
  };
  enter(bucket_);
  Nanos last = last_;
  std::uint64_t count = 0;
  std::uint64_t sum = 0;
  const auto store_run = [&] {
    counts_[bucket] += count;
    sums_[bucket] += sum;
    spacings_ += count;
    count = 0;
    sum = 0;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const Nanos t = times[i];
    if (last != kUnknownTime && t >= last) {
      const Nanos spacing = std::min(t - last, kTop);
      if (spacing < from || spacing >= below) {
        store_run();
        enter(index.find(spacing));
      }
      ++count;
      sum += static_cast<std::uint64_t>(spacing);
    }
    last = t;
  }
  store_run();
  last_ = last;
  bucket_ = bucket;
}

std::optional<Nanos> LineCheck::byte_spacing(Nanos precision) const {
  const auto cluster = densest_cluster(precision);
  if (!cluster) return std::nullopt;
  return cluster->spacing;
}

std::optional<InferredLine> LineCheck::infer_line(
    Nanos precision, std::optional<std::uint32_t> bits_per_char) const {
  const auto cluster = densest_cluster(precision);
  if (!cluster) return std::nullopt;
  std::array<std::uint32_t, 3> sizes = {11, 10, 12};
  const std::size_t tries = bits_per_char ? 1 : sizes.size();
  if (bits_per_char) sizes[0] = *bits_per_char;
  for (std::size_t i = 0; i < tries; ++i) {
    if (auto baud = nearest_standard_baud(rate_at(cluster->spacing, sizes[i]))) {
      return InferredLine{*baud, sizes[i], cluster->spacing, cluster->count, spacings_};
    }
  }
  return std::nullopt;
}

std::optional<LineCheck::Cluster> LineCheck::densest_cluster(Nanos precision) const {
  // Same bar as the timing estimator: up to 2% of batched reads leave per-byte timing intact.
  if (chunks_ == 0 || multi_byte_chunks_ * 50 > chunks_) return std::nullopt;
  std::uint64_t best_count = 0;
  std::uint64_t best_sum = 0;
  std::uint64_t count = 0;
  std::uint64_t sum = 0;
  for (std::size_t b = 0; b < kBuckets; ++b) {
    count += counts_[b];
    sum += sums_[b];
    if (b >= kClusterBuckets) {
      count -= counts_[b - kClusterBuckets];
      sum -= sums_[b - kClusterBuckets];
    }
    if (count > best_count) {
      best_count = count;
      best_sum = sum;
    }
  }
  if (best_count < kMinCluster || best_count * kMinClusterShareDenominator < spacings_) {
    return std::nullopt;  // no spacing most bytes share
  }
  const auto spacing = static_cast<Nanos>(best_sum / best_count);
  // Bytes stamped closer than the timestamps can show, or less than 1 µs apart, are reads
  // stamped one by one, not a line's characters.
  if (spacing < kNanosPerMicro || spacing < precision * 10) return std::nullopt;
  return Cluster{spacing, best_count};
}

std::optional<std::string> LineCheck::warning(const LineSettings& line, Nanos precision) const {
  const Nanos char_time = line.char_time();
  // Timestamps too coarse to measure a tenth of a character cannot contradict the settings.
  if (precision * 10 > char_time) return std::nullopt;
  const auto spacing = byte_spacing(precision);
  if (!spacing) return std::nullopt;
  const double chars = static_cast<double>(*spacing) / static_cast<double>(char_time);
  if (chars < kShortBelow) {
    const Likely likely = standard_line(*spacing, line).value_or(measured_line(*spacing, line));
    return fmt::format(
        "bytes arrive {:.3f} ms apart, shorter than one character at {} baud "
        "({:.3f} ms): {}",
        millis(*spacing), line.baud, millis(char_time), likely_text(likely, line));
  }
  if (chars >= kLongFrom) {
    // Only a standard rate makes a slower line likelier than a device that pauses.
    const auto likely = standard_line(*spacing, line);
    if (!likely) return std::nullopt;
    return fmt::format(
        "bytes arrive {:.3f} ms apart, {:.1f} characters at {} baud ({:.3f} ms), as if every "
        "byte were followed by a pause: {}",
        millis(*spacing), chars, line.baud, millis(char_time), likely_text(*likely, line));
  }
  return std::nullopt;
}

}  // namespace rtu
