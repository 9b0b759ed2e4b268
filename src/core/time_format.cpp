#include "core/time_format.hpp"

#include <array>
#include <iterator>

namespace rtu {
namespace {

constexpr std::array<Nanos, 10> kPow10 = {1,      10,      100,      1000,      10000,
                                          100000, 1000000, 10000000, 100000000, 1000000000};

void append_fixed(fmt::memory_buffer& out, Nanos value, Nanos unit, int decimals) {
  // value / unit with `decimals` digits, floor rounding, without overflow for any int64.
  Nanos whole = value / unit;
  Nanos rest = value % unit;
  if (rest < 0) {
    rest += unit;
    --whole;
  }
  const Nanos scale = unit / kPow10[static_cast<std::size_t>(decimals)];
  const Nanos frac = rest / scale;
  if (whole < 0 && frac != 0) {
    // e.g. -0.25 s: floor gives whole=-1, frac=0.75; print as -0.25 instead.
    const Nanos neg_rest = unit - rest;
    fmt::format_to(std::back_inserter(out), "-{}.{:0{}d}", -(whole + 1), neg_rest / scale,
                   decimals);
    return;
  }
  if (decimals == 0) {
    fmt::format_to(std::back_inserter(out), "{}", whole);
  } else {
    fmt::format_to(std::back_inserter(out), "{}.{:0{}d}", whole, frac, decimals);
  }
}

}  // namespace

void append_seconds(fmt::memory_buffer& out, Nanos t, int decimals) {
  append_fixed(out, t, kNanosPerSecond, decimals < 0 ? 0 : (decimals > 9 ? 9 : decimals));
}

void append_millis(fmt::memory_buffer& out, Nanos t) {
  append_fixed(out, t, kNanosPerMilli, 3);
}

}  // namespace rtu
