#pragma once
// Text from outside (mesh files, paths, scripts) shown in a message or log:
// printable ASCII and well-formed UTF-8 stay as they are; control bytes,
// DEL and bytes that are not well-formed UTF-8 become \xNN, so a message can
// neither drive a terminal (escape sequences) nor be cut short (NUL).
#include <cstddef>
#include <string>
#include <string_view>

namespace softcut {

// At most `max_bytes` of the input are shown; "..." marks a cut.
// `multiline`: newlines and tabs stay (tracebacks), every other control
// byte is still escaped.
std::string printable(std::string_view text, std::size_t max_bytes = 200, bool multiline = false);

// Length of the well-formed UTF-8 sequence starting at s[0] (1..4), or 0.
std::size_t utf8_sequence_length(std::string_view s);

}  // namespace softcut
