#pragma once
// How readers quote the offending input in error messages: "'0G'", "'\x00'", "end of line".
#include <string>
#include <string_view>

namespace rtu {

// `text` in single quotes, with control and non-ASCII bytes escaped (\t, \xNN) and cut after
// 24 characters ("..."); "end of line" when empty.
std::string found_text(std::string_view text);

// The word starting at `pos` (up to a space, tab or `stop` character), for found_text().
std::string_view word_at(std::string_view line, std::size_t pos, char stop = '\0');

}  // namespace rtu
