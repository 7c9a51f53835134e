// Ramp, path and tissue bindings: the engine checks and evaluates them, so a
// scenario's Ramp:at / Path:at give exactly what the run uses.
#include "bindings.hpp"
#include "convert.hpp"
#include "runtime.hpp"
#include "sim/tissue.hpp"
#include "tools/path.hpp"
#include "tools/ramp.hpp"

namespace softcut::lua {

namespace {

std::string where_of(lua_State* L, const char* what) {
  return cat(user_where(L), ": ", what, ".", get_string(L, 1, "kind"));
}

// ramp_check(ramp) -> nil | message (with file:line)
int ramp_check(lua_State* L) {
  return protect(L, [L] {
    const std::string where = where_of(L, "ramp");
    try {
      tools::check_ramp(to_ramp(L, 1), where);
      return 0;
    } catch (const Error& e) {
      lua_pushstring(L, e.what());
      return 1;
    }
  });
}

// ramp_at(ramp, t) -> value
int ramp_at(lua_State* L) {
  return protect(L, [L] {
    const double t = luaL_checknumber(L, 2);
    // Checked here too: the script may have changed the ramp's lists after
    // softcut.ramp.* checked them (times longer than values).
    const tools::Ramp r = to_ramp(L, 1);
    tools::check_ramp(r, "ramp");
    lua_pushnumber(L, tools::evaluate(r, t));
    return 1;
  });
}

int path_check(lua_State* L) {
  return protect(L, [L] {
    const std::string where = where_of(L, "path");
    try {
      tools::check_path(to_path(L, 1), where);
      return 0;
    } catch (const Error& e) {
      lua_pushstring(L, e.what());
      return 1;
    }
  });
}

int path_at(lua_State* L) {
  return protect(L, [L] {
    const double t = luaL_checknumber(L, 2);
    const tools::Path p = to_path(L, 1);  // checked again: see ramp_at
    tools::check_path(p, "path");
    push_vec3(L, tools::evaluate(p, t));
    return 1;
  });
}

// tissue_presets() -> { {name, young, poisson, source}, ... }
int tissue_presets(lua_State* L) {
  return protect(L, [L] {
    const auto& presets = sim::tissue_presets();
    lua_createtable(L, int(presets.size()), 0);
    for (size_t i = 0; i < presets.size(); ++i) {
      lua_createtable(L, 0, 4);
      lua_pushstring(L, presets[i].name.c_str());
      lua_setfield(L, -2, "name");
      lua_pushnumber(L, presets[i].material.young);
      lua_setfield(L, -2, "young");
      lua_pushnumber(L, presets[i].material.poisson);
      lua_setfield(L, -2, "poisson");
      lua_pushstring(L, presets[i].source.c_str());
      lua_setfield(L, -2, "source");
      lua_rawseti(L, -2, lua_Integer(i + 1));
    }
    return 1;
  });
}

int tissue_known(lua_State* L) {
  const char* name = luaL_checkstring(L, 1);
  bool known = false;
  for (const auto& p : sim::tissue_presets()) known = known || p.name == name;
  lua_pushboolean(L, known);
  return 1;
}

}  // namespace

const luaL_Reg kToolFunctions[] = {
    {"ramp_check", ramp_check},         {"ramp_at", ramp_at},           {"path_check", path_check},
    {"path_at", path_at},               {"tissue_presets", tissue_presets}, {"tissue_known", tissue_known},
    {nullptr, nullptr}};

}  // namespace softcut::lua
