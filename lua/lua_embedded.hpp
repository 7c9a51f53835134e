#pragma once
// The Lua-side library compiled into the binary (generated from lua/*.lua).
#include <string_view>
#include <vector>

namespace softcut::lua {
struct EmbeddedScript {
  std::string_view name;    // module name: file name without .lua
  std::string_view source;  // Lua source text
};
const std::vector<EmbeddedScript>& embedded_scripts();
}  // namespace softcut::lua
