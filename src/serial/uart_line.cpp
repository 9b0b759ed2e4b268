#include "serial/uart_line.hpp"

#include <algorithm>

#include "core/chunk.hpp"

namespace rtu {
namespace {

bool parity_bit(std::uint8_t byte, Parity parity) {
  const bool odd_ones = (__builtin_popcount(byte) & 1) != 0;
  // Even parity makes the count of ones, parity bit included, even.
  return parity == Parity::kEven ? odd_ones : !odd_ones;
}

}  // namespace

Picos half_bits_at(std::uint32_t baud, std::int64_t half_bits) {
  return half_bits * kPicosPerSecond / (2 * static_cast<Picos>(baud));
}

Picos char_duration(const LineSettings& line) {
  return half_bits_at(line.baud, 2 * static_cast<std::int64_t>(line.bits_per_char()));
}

void LineLevels::set(Picos t, bool level) {
  const bool current = changes_.empty() ? initial_ : changes_.back().second;
  if (level == current) return;
  if (!changes_.empty() && changes_.back().first == t) {
    changes_.pop_back();  // a zero-length level: the new one replaces it
    const bool before = changes_.empty() ? initial_ : changes_.back().second;
    if (before == level) return;
  }
  changes_.emplace_back(t, level);
}

bool LineLevels::level_at(Picos t) const {
  // The last change at or before t.
  const auto it = std::upper_bound(changes_.begin(), changes_.end(), t,
                                   [](Picos value, const auto& c) { return value < c.first; });
  return it == changes_.begin() ? initial_ : std::prev(it)->second;
}

std::optional<Picos> LineLevels::falling_edge_from(Picos from) const {
  auto it = std::lower_bound(changes_.begin(), changes_.end(), from,
                             [](const auto& c, Picos value) { return c.first < value; });
  for (; it != changes_.end(); ++it) {
    if (!it->second) return it->first;  // changes alternate: a change to 0 is a fall
  }
  return std::nullopt;
}

void LineLevels::forget_before(Picos t) {
  const auto it = std::lower_bound(changes_.begin(), changes_.end(), t,
                                   [](const auto& c, Picos value) { return c.first < value; });
  if (it == changes_.begin()) return;
  initial_ = std::prev(it)->second;
  changes_.erase(changes_.begin(), it);
}

Picos render_char(LineLevels& line, Picos start, std::uint8_t byte, const LineSettings& tx,
                  bool inverted) {
  std::vector<bool> bits;
  bits.push_back(false);  // start
  for (unsigned i = 0; i < 8; ++i) bits.push_back(((static_cast<unsigned>(byte) >> i) & 1U) != 0);
  if (tx.parity != Parity::kNone) bits.push_back(parity_bit(byte, tx.parity));
  for (unsigned i = 0; i < tx.stop_bits; ++i) bits.push_back(true);
  for (std::size_t i = 0; i < bits.size(); ++i) {
    line.set(start + half_bits_at(tx.baud, 2 * static_cast<std::int64_t>(i)), bits[i] != inverted);
  }
  return start + char_duration(tx);
}

Picos UartReceiver::stop_sample_offset() const {
  const std::int64_t stop_index = 9 + (rx_.parity == Parity::kNone ? 0 : 1);
  return half_bits_at(rx_.baud, 2 * stop_index + 1);
}

void UartReceiver::receive(const LineLevels& line, Picos known_until,
                           std::vector<ReceivedChar>& out) {
  for (;;) {
    const auto edge = line.falling_edge_from(resume_);
    if (!edge || *edge + stop_sample_offset() >= known_until) return;
    const Picos e = *edge;
    auto sample = [&](std::int64_t bit) {
      return line.level_at(e + half_bits_at(rx_.baud, 2 * bit + 1));
    };
    if (sample(0)) {  // back at 1 by mid start bit: a glitch, not a character
      resume_ = e + half_bits_at(rx_.baud, 1);
      continue;
    }
    ReceivedChar c;
    c.start = e;
    bool all_zero = true;
    for (unsigned i = 0; i < 8; ++i) {
      if (sample(1 + i)) {
        c.byte = static_cast<std::uint8_t>(c.byte | (1U << i));
        all_zero = false;
      }
    }
    std::int64_t next = 9;
    bool parity_ok = true;
    if (rx_.parity != Parity::kNone) {
      const bool p = sample(next++);
      all_zero = all_zero && !p;
      parity_ok = p == parity_bit(c.byte, rx_.parity);
    }
    const bool stop = sample(next);
    if (!stop && all_zero) {
      c.error = kBreak;
    } else if (!stop) {
      c.error = kFramingError;  // it may have a parity error too: in-band marks cannot say
    } else if (!parity_ok) {
      c.error = kParityError;
    }
    c.end = e + half_bits_at(rx_.baud, 2 * next + 2);
    resume_ = e + stop_sample_offset();
    out.push_back(c);
  }
}

std::optional<Picos> UartReceiver::next_complete(const LineLevels& line) const {
  const auto edge = line.falling_edge_from(resume_);
  if (!edge) return std::nullopt;
  return *edge + stop_sample_offset() + 1;
}

void UartReceiver::reconfigure(const LineSettings& rx, Picos from) {
  rx_ = rx;
  resume_ = std::max(resume_, from);
}

std::vector<ReceivedChar> transmit_and_receive(const std::vector<std::uint8_t>& bytes,
                                               const LineSettings& tx, const LineSettings& rx,
                                               bool inverted) {
  LineLevels line(!inverted);
  // One idle character first, as a line that has been quiet.
  Picos t = char_duration(tx);
  for (const auto b : bytes) t = render_char(line, t, b, tx, inverted);
  UartReceiver receiver(rx);
  std::vector<ReceivedChar> out;
  receiver.receive(line, t + 4 * std::max(char_duration(tx), char_duration(rx)), out);
  return out;
}

}  // namespace rtu
