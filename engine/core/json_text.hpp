#pragma once
// JSON string literals for the hand-assembled JSON writers (summary.json, the
// bench reports): escaped by nlohmann-json, so every byte value gives valid
// JSON (control characters as \uXXXX; bytes that are not well-formed UTF-8
// become U+FFFD).
#include <string>
#include <string_view>

namespace softcut {

// "\"...\"": the quoted, escaped JSON string for `s`.
std::string json_string(std::string_view s);

}  // namespace softcut
