#pragma once
// The embedded Lua-side library (lua/*.lua, compiled into the program):
// `require` for its modules (their bytecode compiled once per process) and
// for the scenario's own modules below its folder, the private table the
// library reaches the C++ bindings through, and the `softcut` global.
struct lua_State;

namespace softcut::lua {

struct SandboxOptions;

// Registry key of the library's private table (bindings, overrides,
// scenario_dir): Runtime::push_internal.
inline constexpr const char* kInternalKey = "softcut.internal";

// Sets up `require`: in the sandbox the library's own (embedded modules,
// then the scenario's below its folder); with --trust the embedded modules
// as a searcher before Lua's own, and the scenario's folder first on
// package.path. Inside a protected call or before any script runs.
void install_require(lua_State* L, const SandboxOptions& opt);
// Makes the private table (with the engine bindings) and the `softcut`
// global; call inside a protected call.
void open_library(lua_State* L);
// Pushes the `softcut` library table (loads it on first use).
void push_library(lua_State* L);

}  // namespace softcut::lua
