#pragma once
// Plain Lua tables (built and checked by the Lua-side library) -> engine
// structs. The tables were checked in Lua already; these readers still throw
// softcut::Error on anything unexpected rather than guess. Call them only
// inside protect() or Runtime::call (they use the Lua stack).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "sim/selector.hpp"
#include "tools/path.hpp"
#include "tools/ramp.hpp"

struct lua_State;

namespace softcut::lua {

// Fields of the table at `idx`; `what` names it in errors.
bool has_field(lua_State* L, int idx, const char* key);
double get_number(lua_State* L, int idx, const char* key, double fallback);
int get_int(lua_State* L, int idx, const char* key, int fallback);
bool get_bool(lua_State* L, int idx, const char* key, bool fallback);
std::string get_string(lua_State* L, int idx, const char* key, const std::string& fallback = {});
Eigen::Vector3d get_vec3(lua_State* L, int idx, const char* key, const Eigen::Vector3d& fallback);
std::vector<double> get_numbers(lua_State* L, int idx, const char* key);
std::vector<int> get_ints(lua_State* L, int idx, const char* key);
std::vector<Eigen::Vector3d> get_vec3s(lua_State* L, int idx, const char* key);

// The value at `idx` as a vec3 {x, y, z}.
Eigen::Vector3d to_vec3(lua_State* L, int idx);
void push_vec3(lua_State* L, const Eigen::Vector3d& v);
void push_ints(lua_State* L, const std::vector<int>& v);

tools::Ramp to_ramp(lua_State* L, int idx);
tools::Path to_path(lua_State* L, int idx);
// Set operations come out flat where they chain (a + b + c: one union of
// three); nesting over 200 levels or over 1e5 parts is an Error.
sim::NodeSelector to_node_selector(lua_State* L, int idx);
// Shapes and set operations in a selection (the work of evaluating it is
// about this many passes over the nodes).
int selection_parts(const sim::NodeSelector& s);
sim::TetSelector to_tet_selector(lua_State* L, int idx);

// One line describing a selection or region table (for "selects no node").
std::string describe_selection(lua_State* L, int idx);

}  // namespace softcut::lua
