#pragma once
// A warning that CI may act on carries a stable code (lower_snake_case, e.g.
// implausible_size), written at the end of its text as compilers write
// theirs:
//   mesh: the body is 190 m across ... unit = "mm" ... [implausible_size]
// The code travels with the text through every list of warnings
// (Diagnostics, the Model's and the State's, summary.json's `warnings`,
// stderr), so no list changes type to carry it; warning_code() reads it back.
#include <string>
#include <string_view>

#include "core/error.hpp"

namespace softcut {

inline std::string coded_warning(std::string_view code, std::string_view message) {
  return cat(message, " [", code, "]");
}

// The code of a warning made by coded_warning, or "" when it has none.
inline std::string_view warning_code(std::string_view warning) {
  if (warning.size() < 4 || warning.back() != ']') return {};
  const std::size_t open = warning.rfind(" [");
  if (open == std::string_view::npos) return {};
  const std::string_view code = warning.substr(open + 2, warning.size() - open - 3);
  if (code.empty() || !(code[0] >= 'a' && code[0] <= 'z')) return {};
  for (const char c : code)
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return {};
  return code;
}

// diag.warn with a code.
template <class... Args>
void warn_coded(Diagnostics& diag, std::string_view code, const Args&... args) {
  diag.warnings.push_back(coded_warning(code, cat(args...)));
}

}  // namespace softcut
