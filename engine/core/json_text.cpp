#include "core/json_text.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace softcut {

Json json_number(double v, int digits) {
  if (!std::isfinite(v)) return nullptr;
  // Through the decimal text: the shortest double that prints back as it
  // (what the dump writes) has at most `digits` significant digits.
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return std::strtod(buf, nullptr);
}

std::string json_text(const Json& j) {
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

}  // namespace softcut
