#pragma once
// The JSON files softcut writes (summary.json, sweep and bench reports, mesh
// info) are built as nlohmann-json documents and written through here, so
// every one is valid JSON whatever its strings hold: control characters
// become \uXXXX, bytes that are not well-formed UTF-8 become U+FFFD.
#include <nlohmann/json.hpp>
#include <string>

namespace softcut {

// Keys stay in the order they were set: the files read in the order their
// schema documents them.
using Json = nlohmann::ordered_json;

// A double as JSON: rounded to `digits` significant digits (a time of
// 12.3456789 ms reads 12.3457 at 6, not as 17 digits); NaN and infinities,
// which JSON has no number for, become null.
Json json_number(double v, int digits = 15);

// The document as text: 2-space indented, with a final newline.
std::string json_text(const Json& j);

}  // namespace softcut
