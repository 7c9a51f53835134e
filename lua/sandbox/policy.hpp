#pragma once
// What a script may reach in the sandbox: the safe standard libraries, load
// for text chunks only, io through the checked opens (sandbox/io.cpp), os
// trimmed to the clocks, string patterns bounded by their worst-case work
// (sandbox/patterns.hpp), and every removed name refused with a message
// that says how to get it back (--trust). The budgets themselves are in
// sandbox/limits.hpp.
struct lua_State;

namespace softcut::lua {

// Opens the sandboxed libraries into L's globals and installs the budgets'
// wrappers (install_sandbox_limits).
void open_sandbox(lua_State* L);

}  // namespace softcut::lua
