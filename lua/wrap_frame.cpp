// Frame bindings for on_frame and expectations: read the State, steer tools
// and loads between frames, request a stop.
#include <cmath>
#include <optional>
#include <string_view>

#include "bindings.hpp"
#include "convert.hpp"
#include "runtime.hpp"
#include "wrap_frame.hpp"

#include "sim/control.hpp"

namespace softcut::lua {

namespace {

const char* kFrameMeta = "softcut.FrameContext";

FrameContext& ctx(lua_State* L) {
  auto* c = static_cast<FrameContext*>(luaL_checkudata(L, 1, kFrameMeta));
  if (!c->model || !c->state) fail("this frame is over: use the frame only inside its on_frame call");
  return *c;
}

int node_of(lua_State* L, const FrameContext& c, int idx) {
  const lua_Integer n = luaL_checkinteger(L, idx);
  const lua_Integer nn = c.state->displacement.rows();  // grows when cutting adds nodes
  if (n < 0 || n >= nn) fail("node ", n, " out of range (the mesh has ", nn, " nodes now)");
  return int(n);
}

// Node ids from Lua (a selection's cached ids, which a script can overwrite),
// each checked against the current node count (reading them is charged).
std::vector<int> ids_of(lua_State* L, int idx, const FrameContext& c, const char* fname) {
  lua_newtable(L);
  lua_pushvalue(L, idx);
  lua_setfield(L, -2, "ids");
  std::vector<int> ids = get_ints(L, -1, "ids");
  lua_pop(L, 1);
  const Eigen::Index nn = c.state->displacement.rows();  // grows when cutting adds nodes
  for (int n : ids)
    if (n < 0 || n >= nn) fail(user_prefix(L), fname, ": node ", n, " out of range (the mesh has ", nn, " nodes now)");
  return ids;
}

template <class Vec>
int tool_index(lua_State* L, const Vec& tools, int idx) {
  const lua_Integer i = luaL_checkinteger(L, idx);
  if (i < 0 || i >= lua_Integer(tools.size())) fail("tool index ", i, " out of range");
  return int(i);
}

int frame_displacement(lua_State* L) {
  return protect(L, [L] {
    FrameContext& c = ctx(L);
    const int n = node_of(L, c, 2);
    sim::check_solved(*c.model, *c.state, n, user_prefix(L) + "displacement");
    push_vec3(L, c.state->displacement.row(n).transpose());
    return 1;
  });
}

int frame_position(lua_State* L) {
  return protect(L, [L] {
    FrameContext& c = ctx(L);
    const int n = node_of(L, c, 2);
    sim::check_solved(*c.model, *c.state, n, user_prefix(L) + "position");
    push_vec3(L, (sim::current_mesh(*c.model, *c.state).nodes.row(n) + c.state->displacement.row(n)).transpose());
    return 1;
  });
}

int frame_mean_displacement(lua_State* L) {
  return protect(L, [L] {
    FrameContext& c = ctx(L);
    const std::vector<int> ids = ids_of(L, 2, c, "mean_displacement");
    for (int n : ids) sim::check_solved(*c.model, *c.state, n, user_prefix(L) + "mean_displacement");
    push_vec3(L, sim::mean_displacement(*c.state, ids));
    return 1;
  });
}

int frame_max_displacement(lua_State* L) {
  return protect(L, [L] {
    FrameContext& c = ctx(L);
    double m = 0;
    for (int n : ids_of(L, 2, c, "max_displacement")) {
      sim::check_solved(*c.model, *c.state, n, user_prefix(L) + "max_displacement");
      m = std::max(m, c.state->displacement.row(n).norm());
    }
    lua_pushnumber(L, m);
    return 1;
  });
}

int frame_tool(lua_State* L) {
  return protect(L, [L] {
    FrameContext& c = ctx(L);
    const tools::ToolState& t = c.state->tools[tool_index(L, c.state->tools, 2)];
    lua_createtable(L, 0, 4);
    push_vec3(L, t.tip);
    lua_setfield(L, -2, "tip");
    lua_pushboolean(L, t.engaged);
    lua_setfield(L, -2, "engaged");
    lua_pushinteger(L, lua_Integer(t.nodes.size()));
    lua_setfield(L, -2, "num_nodes");
    push_vec3(L, t.total_force);
    lua_setfield(L, -2, "force");
    lua_pushnumber(L, t.pressure);
    lua_setfield(L, -2, "pressure");
    lua_pushboolean(L, t.cutting);
    lua_setfield(L, -2, "cutting");
    return 1;
  });
}

int frame_cutting(lua_State* L) {
  return protect(L, [L] {
    FrameContext& c = ctx(L);
    const int tets = sim::current_mesh(*c.model, *c.state).num_tets();
    charge_work(L, 2.0 * tets, "f:cutting");  // counting the pieces visits every tet twice
    const sim::CuttingSummary cs = sim::cutting_summary(*c.model, *c.state);
    lua_createtable(L, 0, 9);
    for (const auto& [name, value] : {std::pair{"events", cs.events}, {"nodes_added", cs.nodes_added},
                                      {"nodes", cs.nodes}, {"tets", cs.tets}, {"faces_separated", cs.faces_separated},
                                      {"faces_pending", cs.faces_pending}, {"components", cs.components},
                                      {"pieces", cs.pieces}, {"detached", cs.detached}}) {
      lua_pushinteger(L, value);
      lua_setfield(L, -2, name);
    }
    return 1;
  });
}

// The run-control calls: arguments converted here, the change made by
// sim/control.hpp.
int frame_move_tool(lua_State* L) {
  return protect(L, [L] {
    FrameContext& c = ctx(L);
    const int i = tool_index(L, c.state->tools, 2);
    sim::move_tool(*c.state, i, lua_isnoneornil(L, 3) ? std::nullopt : std::optional(to_vec3(L, 3)));
    return 0;
  });
}

int frame_enable_tool(lua_State* L) {
  return protect(L, [L] {
    FrameContext& c = ctx(L);
    sim::enable_tool(*c.state, tool_index(L, c.state->tool_specs, 2), lua_toboolean(L, 3));
    return 0;
  });
}

// frame_set_load(ctx, index, scale|nil, enabled|nil)
int frame_set_load(lua_State* L) {
  return protect(L, [L] {
    FrameContext& c = ctx(L);
    const int i = tool_index(L, c.state->loads, 2);
    sim::set_load(*c.state, i, lua_isnoneornil(L, 3) ? std::nullopt : std::optional(luaL_checknumber(L, 3)),
                  lua_isnoneornil(L, 4) ? std::nullopt : std::optional(bool(lua_toboolean(L, 4))));
    return 0;
  });
}

int frame_stop(lua_State* L) {
  return protect(L, [L] {
    sim::request_stop(*ctx(L).state);
    return 0;
  });
}

// frame_record(ctx, name, value)
int frame_record(lua_State* L) {
  return protect(L, [L] {
    size_t len = 0;
    const char* name = luaL_checklstring(L, 2, &len);
    sim::record_metric(*ctx(L).state, std::string_view(name, len), luaL_checknumber(L, 3));
    return 0;
  });
}

}  // namespace

FrameContext* push_frame_context(lua_State* L) {
  auto* c = static_cast<FrameContext*>(lua_newuserdatauv(L, sizeof(FrameContext), 0));
  *c = FrameContext{};
  if (luaL_newmetatable(L, kFrameMeta)) {
    lua_pushstring(L, "Frame");
    lua_setfield(L, -2, "__name");
    lua_pushboolean(L, 0);  // locked: no script can give frame handles a __gc
    lua_setfield(L, -2, "__metatable");
  }
  lua_setmetatable(L, -2);
  return c;
}

const luaL_Reg kFrameFunctions[] = {
    {"frame_displacement", frame_displacement},
    {"frame_position", frame_position},
    {"frame_mean_displacement", frame_mean_displacement},
    {"frame_max_displacement", frame_max_displacement},
    {"frame_tool", frame_tool},
    {"frame_cutting", frame_cutting},
    {"frame_move_tool", frame_move_tool},
    {"frame_enable_tool", frame_enable_tool},
    {"frame_set_load", frame_set_load},
    {"frame_stop", frame_stop},
    {"frame_record", frame_record},
    {nullptr, nullptr}};

}  // namespace softcut::lua
