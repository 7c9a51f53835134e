#include "bindings.hpp"

#include "wrap_mesh.hpp"

namespace softcut::lua {

void open_bindings(lua_State* L) {
  register_mesh_meta(L);
  for (const luaL_Reg* regs : {kMeshFunctions, kToolFunctions, kFrameFunctions}) luaL_setfuncs(L, regs, 0);
  lua_pushstring(L, SOFTCUT_VERSION);
  lua_setfield(L, -2, "version");
}

}  // namespace softcut::lua
