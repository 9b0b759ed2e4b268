#pragma once
// What every fuzz target of a reader or loader asserts about its errors: a message that
// says where ("NAME:LINE: ...", "NAME:LINE:COL: ..." or "NAME: offset N: ..."), so a user
// can find the damage. A failed oracle aborts, and libFuzzer keeps the input.
#include <cstdint>
#include <optional>
#include <string_view>

namespace rtu::fuzz {

[[noreturn]] void fail(std::string_view target, std::string_view what, std::string_view detail);

struct Place {
  enum class Kind : std::uint8_t { kLine, kOffset };
  Kind kind = Kind::kLine;
  std::uint64_t number = 0;
};

// The place a message names right after `name`, or nullopt when it names none.
std::optional<Place> place_in_message(std::string_view message, std::string_view name);

// Aborts unless `message` names a line (1 ≤ line ≤ `max_line`) of `name`.
void require_line(std::string_view target, std::string_view message, std::string_view name,
                  std::uint64_t max_line);
// Aborts unless `message` names an offset ≤ `size` of `name`.
void require_offset(std::string_view target, std::string_view message, std::string_view name,
                    std::uint64_t size);

// Lines of `text` (a last line without '\n' counts), and at least 1: an empty file has a
// line 1 an error may name.
std::uint64_t count_lines(std::string_view text);

}  // namespace rtu::fuzz
