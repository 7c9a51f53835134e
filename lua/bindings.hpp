#pragma once
// The engine bindings the Lua-side library reaches through its `internal`
// table (never the scenario directly). Each wrap_<topic>.cpp checks its
// arguments, calls one engine function, pushes the result, and exports a
// luaL_Reg table; open_bindings() copies them into the table on the stack.
#include <lua.hpp>

namespace softcut::lua {

extern const luaL_Reg kMeshFunctions[];   // wrap_mesh.cpp: mesh_load, select_nodes, count_tets, ...
extern const luaL_Reg kToolFunctions[];   // wrap_tools.cpp: ramp_check, ramp_at, path_check, path_at, tissues
extern const luaL_Reg kFrameFunctions[];  // wrap_frame.cpp: frame_displacement, frame_move_tool, ...

// Fills the table on top of the stack with every binding.
void open_bindings(lua_State* L);

}  // namespace softcut::lua
