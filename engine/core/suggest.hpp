#pragma once
// " (did you mean 'x'?)" for a misspelt name, as the Lua side's
// check.suggest words it (lua/check.lua): every parse_X of a spec enum ends
// its error with it, so C++ and Lua errors read alike.
#include <initializer_list>
#include <string>
#include <string_view>

namespace softcut {

// The closest of `names` (case-insensitive optimal string alignment
// distance, a prefix counting as 1) when within max(1, |word| / 3) edits:
// " (did you mean 'x'?)"; else " (valid: a, b, c)", sorted.
std::string suggest(std::string_view word, std::initializer_list<std::string_view> names);

}  // namespace softcut
