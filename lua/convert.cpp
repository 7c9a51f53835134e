#include "convert.hpp"

#include <lua.hpp>

#include <cmath>

#include "core/error.hpp"
#include "runtime.hpp"

namespace softcut::lua {

namespace {

// Pushes t[key] (raw: the tables are plain data) and returns its type.
// Whatever sits at idx came from a script, which may have put a number or
// a string where a table belongs: refused before any raw access (which on
// a non-table reads through whatever pointer it holds).
int field(lua_State* L, int idx, const char* key) {
  idx = lua_absindex(L, idx);
  if (lua_type(L, idx) != LUA_TTABLE)
    fail("expected a table with field '", key, "', got ", lua_typename(L, lua_type(L, idx)));
  lua_pushstring(L, key);
  return lua_rawget(L, idx);
}

struct Pop {
  lua_State* L;
  int n;
  ~Pop() { lua_pop(L, n); }
};

}  // namespace

bool has_field(lua_State* L, int idx, const char* key) {
  const bool r = field(L, idx, key) != LUA_TNIL;
  lua_pop(L, 1);
  return r;
}

double get_number(lua_State* L, int idx, const char* key, double fallback) {
  const int t = field(L, idx, key);
  Pop p{L, 1};
  if (t == LUA_TNIL) return fallback;
  if (t != LUA_TNUMBER) fail("field '", key, "' must be a number, got ", lua_typename(L, t));
  return lua_tonumber(L, -1);
}

int get_int(lua_State* L, int idx, const char* key, int fallback) {
  const double d = get_number(L, idx, key, fallback);
  if (d != std::floor(d) || std::abs(d) > 2e9) fail("field '", key, "' must be an integer, got ", d);
  return int(d);
}

bool get_bool(lua_State* L, int idx, const char* key, bool fallback) {
  const int t = field(L, idx, key);
  Pop p{L, 1};
  if (t == LUA_TNIL) return fallback;
  if (t != LUA_TBOOLEAN) fail("field '", key, "' must be a boolean, got ", lua_typename(L, t));
  return lua_toboolean(L, -1);
}

std::string get_string(lua_State* L, int idx, const char* key, const std::string& fallback) {
  const int t = field(L, idx, key);
  Pop p{L, 1};
  if (t == LUA_TNIL) return fallback;
  if (t != LUA_TSTRING) fail("field '", key, "' must be a string, got ", lua_typename(L, t));
  size_t n = 0;
  const char* s = lua_tolstring(L, -1, &n);
  return std::string(s, n);
}

Eigen::Vector3d to_vec3(lua_State* L, int idx) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) fail("expected a 3-vector {x, y, z}, got ", luaL_typename(L, idx));
  Eigen::Vector3d v;
  for (int c = 0; c < 3; ++c) {
    if (lua_rawgeti(L, idx, c + 1) != LUA_TNUMBER) {
      lua_pop(L, 1);
      fail("expected a 3-vector {x, y, z} of numbers");
    }
    v(c) = lua_tonumber(L, -1);
    lua_pop(L, 1);
  }
  return v;
}

Eigen::Vector3d get_vec3(lua_State* L, int idx, const char* key, const Eigen::Vector3d& fallback) {
  const int t = field(L, idx, key);
  Pop p{L, 1};
  if (t == LUA_TNIL) return fallback;
  try {
    return to_vec3(L, -1);
  } catch (const Error& e) {
    fail("field '", key, "': ", e.what());
  }
}

// Reading a list from Lua is native work, charged to the sandbox's
// instruction budget per entry: a rawgeti is about one Lua instruction's
// work, and each number copied is kept (and copied again by compile), so a
// list the script shares among many entries costs per copy.
constexpr double kInstructionsPerEntry = 4;

std::vector<double> get_numbers(lua_State* L, int idx, const char* key) {
  std::vector<double> out;
  const int t = field(L, idx, key);
  Pop p{L, 1};
  if (t == LUA_TNIL) return out;
  if (!lua_istable(L, -1)) fail("field '", key, "' must be a list of numbers");
  const auto n = static_cast<lua_Integer>(lua_rawlen(L, -1));  // raw: no __len runs here
  for (lua_Integer i = 1; i <= n; ++i) {
    if (lua_rawgeti(L, -1, i) != LUA_TNUMBER) {
      lua_pop(L, 1);
      fail("field '", key, "' entry ", i, " must be a number");
    }
    out.push_back(lua_tonumber(L, -1));
    lua_pop(L, 1);
  }
  charge_work(L, kInstructionsPerEntry * double(n), cat("field '", key, "'"));
  return out;
}

std::vector<int> get_ints(lua_State* L, int idx, const char* key) {
  std::vector<int> out;
  for (double d : get_numbers(L, idx, key)) {
    if (d != std::floor(d) || std::abs(d) > 2e9) fail("field '", key, "' entries must be integers, got ", d);
    out.push_back(int(d));
  }
  return out;
}

std::vector<Eigen::Vector3d> get_vec3s(lua_State* L, int idx, const char* key) {
  std::vector<Eigen::Vector3d> out;
  const int t = field(L, idx, key);
  Pop p{L, 1};
  if (t == LUA_TNIL) return out;
  if (!lua_istable(L, -1)) fail("field '", key, "' must be a list of 3-vectors");
  const auto n = static_cast<lua_Integer>(lua_rawlen(L, -1));  // raw: no __len runs here
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, -1, i);
    Pop q{L, 1};
    out.push_back(to_vec3(L, -1));
  }
  charge_work(L, 3 * kInstructionsPerEntry * double(n), cat("field '", key, "'"));
  return out;
}

void push_vec3(lua_State* L, const Eigen::Vector3d& v) {
  lua_createtable(L, 3, 0);
  for (int c = 0; c < 3; ++c) {
    lua_pushnumber(L, v(c));
    lua_rawseti(L, -2, c + 1);
  }
}

void push_ints(lua_State* L, const std::vector<int>& v) {
  // The table is made inside a protected call: callers hold C++ objects (the
  // vector itself), and an out-of-memory longjmp from here would skip their
  // destructors; a C++ exception unwinds them. Filling the preallocated
  // array part allocates nothing.
  if (!lua_checkstack(L, 3)) fail("out of Lua stack space");
  lua_pushcfunction(L, [](lua_State* L) -> int {
    lua_createtable(L, int(lua_tointeger(L, 1)), 0);
    return 1;
  });
  lua_pushinteger(L, lua_Integer(v.size()));
  if (lua_pcall(L, 1, 1, 0) != LUA_OK) {
    lua_pop(L, 1);
    fail("memory budget exceeded by a list of ", v.size(), " node ids (drop what the scenario no longer needs, or "
         "run with --trust)");
  }
  for (size_t i = 0; i < v.size(); ++i) {
    lua_pushinteger(L, v[i]);
    lua_rawseti(L, -2, lua_Integer(i + 1));
  }
}

tools::Ramp to_ramp(lua_State* L, int idx) {
  if (lua_type(L, idx) == LUA_TNUMBER) return tools::Ramp::constant_value(lua_tonumber(L, idx));
  if (!lua_istable(L, idx)) fail("expected a ramp (softcut.ramp.*) or a number");
  const std::string where = get_string(L, idx, "where");
  tools::Ramp r;
  r.kind = tools::ramp_kind_from_string(get_string(L, idx, "kind", "constant"), where);
  r.from = get_number(L, idx, "from", 0.0);
  r.to = get_number(L, idx, "to", 0.0);
  r.t0 = get_number(L, idx, "t0", 0.0);
  r.t1 = get_number(L, idx, "t1", 1.0);
  r.times = get_numbers(L, idx, "times");
  r.values = get_numbers(L, idx, "values");
  r.offset = get_number(L, idx, "offset", 0.0);
  r.amplitude = get_number(L, idx, "amplitude", 0.0);
  r.frequency = get_number(L, idx, "frequency", 1.0);
  r.phase = get_number(L, idx, "phase", 0.0);
  return r;
}

tools::Path to_path(lua_State* L, int idx) {
  if (!lua_istable(L, idx)) fail("expected a path (softcut.path.*)");
  const std::string where = get_string(L, idx, "where");
  tools::Path p;
  p.kind = tools::path_kind_from_string(get_string(L, idx, "kind", "fixed"), where);
  p.times = get_numbers(L, idx, "times");
  p.points = get_vec3s(L, idx, "points");
  p.center = get_vec3(L, idx, "center", p.center);
  p.axis = get_vec3(L, idx, "axis", p.axis);
  p.start = get_vec3(L, idx, "start", p.start);
  p.sweep = get_number(L, idx, "sweep", 0.0);
  p.t0 = get_number(L, idx, "t0", 0.0);
  p.t1 = get_number(L, idx, "t1", 1.0);
  return p;
}

// The fields node and tet selectors share (a box, sphere, half-space, label
// or id list, and where the user wrote it).
template <class Selector>
void read_shape_fields(lua_State* L, int idx, Selector& s) {
  s.where = get_string(L, idx, "where");
  s.min = get_vec3(L, idx, "min", s.min);
  s.max = get_vec3(L, idx, "max", s.max);
  s.center = get_vec3(L, idx, "center", s.center);
  s.radius = get_number(L, idx, "radius", 0.0);
  s.point = get_vec3(L, idx, "point", s.point);
  s.normal = get_vec3(L, idx, "normal", s.normal);
  s.label = get_int(L, idx, "label", -1);
  s.ids = get_ints(L, idx, "ids");
}

namespace {

// Nesting a script cannot build by accident: chains of one set operation
// (`sel = sel + box` in a loop) are spliced flat below, so only alternating
// operations nest. The limits also end a selection that contains itself.
constexpr int kMaxSelectionDepth = 200;
constexpr int kMaxSelectionParts = 100000;

sim::NodeSelector convert_node_selector(lua_State* L, int idx, int depth, int& parts);

std::string where_prefix(const sim::NodeSelector& s) {
  return s.where.empty() || s.where == "?" ? "" : s.where + ": ";
}

// Appends the members of the selection at `idx` (whose kind is `kind`) to
// s.children. A member of the same kind with members of its own is spliced
// in (union and intersection are associative; a difference's first member
// may be a difference: (a - b) - c = a - b - c). The pending members wait on
// the Lua stack, so that deep chains need neither recursion nor Lua
// allocations (which could raise a Lua error across these C++ frames);
// lengths are raw, so no metamethod runs.
void convert_children(lua_State* L, int idx, const std::string& kind, sim::NodeSelector& s, int depth, int& parts) {
  const int base = lua_gettop(L);  // pending members above it, the next one on top
  const auto push_members = [&](int tbl) {  // in reverse, so they come off in order
    const int list = lua_gettop(L) + 1;
    if (field(L, tbl, "children") != LUA_TTABLE) {
      lua_pop(L, 1);
      return;
    }
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, list));
    if (n > kMaxSelectionParts - parts || !lua_checkstack(L, int(n) + 8))
      fail(where_prefix(s), "selection: more than ", kMaxSelectionParts,
           " shapes and set operations (built in a loop? or containing itself?); select the nodes with fewer "
           "shapes, or list them with softcut.select.nodes{...}");
    parts += int(n);
    // Each part is copied into the engine's selector (and evaluated again by
    // compile): a member shared a thousand times costs a thousand times.
    charge_work(L, 64 * double(n), "selection");
    for (lua_Integer i = n; i >= 1; --i) lua_rawgeti(L, list, i);
    lua_remove(L, list);
  };
  const auto has_members = [&](int tbl) {
    const bool yes = field(L, tbl, "children") == LUA_TTABLE && lua_rawlen(L, -1) > 0;
    lua_pop(L, 1);
    return yes;
  };
  push_members(idx);
  bool first = true;  // the next member stands first in the (spliced) operation
  while (lua_gettop(L) > base) {
    const int member = lua_gettop(L);
    const bool splice = lua_istable(L, member) && get_string(L, member, "kind") == kind &&
                        (kind != "difference" || first) && has_members(member);
    if (splice) {  // its members take its place; a difference's first member stays first
      push_members(member);
      lua_remove(L, member);
    } else {
      s.children.push_back(convert_node_selector(L, member, depth + 1, parts));
      lua_pop(L, 1);
      first = false;
    }
  }
}

sim::NodeSelector convert_node_selector(lua_State* L, int idx, int depth, int& parts) {
  using K = sim::NodeSelector::Kind;
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) fail("expected a node selection (softcut.select.*)");
  if (!lua_checkstack(L, 8)) fail("selection: nested too deep for the Lua stack");  // 4 slots a level
  sim::NodeSelector s;
  const std::string kind = get_string(L, idx, "kind");
  static const std::pair<const char*, K> kinds[] = {
      {"all", K::all}, {"box", K::box}, {"sphere", K::sphere}, {"halfspace", K::halfspace},
      {"label", K::label}, {"nodes", K::nodes}, {"surface", K::surface}, {"named", K::named},
      {"union_of", K::union_of}, {"intersection", K::intersection}, {"difference", K::difference}};
  bool found = false;
  for (const auto& [name, k] : kinds)
    if (kind == name) s.kind = k, found = true;
  if (!found) fail("unknown selection kind '", kind, "'");
  read_shape_fields(L, idx, s);
  s.name = get_string(L, idx, "name");
  if (depth > kMaxSelectionDepth)
    fail(where_prefix(s), "selection: set operations nested more than ", kMaxSelectionDepth,
         " deep (does it contain itself?); combine the shapes in fewer steps");
  if (s.kind == K::union_of || s.kind == K::intersection || s.kind == K::difference)
    convert_children(L, idx, kind, s, depth, parts);
  return s;
}

}  // namespace

sim::NodeSelector to_node_selector(lua_State* L, int idx) {
  int parts = 0;
  return convert_node_selector(L, idx, 0, parts);
}

int selection_parts(const sim::NodeSelector& s) {
  int n = 1;
  for (const auto& c : s.children) n += selection_parts(c);
  return n;
}

sim::TetSelector to_tet_selector(lua_State* L, int idx) {
  using K = sim::TetSelector::Kind;
  idx = lua_absindex(L, idx);
  sim::TetSelector s;
  if (lua_isnil(L, idx)) return s;  // none
  if (!lua_istable(L, idx)) fail("expected a region table");
  const std::string kind = get_string(L, idx, "kind");
  static const std::pair<const char*, K> kinds[] = {{"all", K::all},       {"none", K::none},
                                                    {"label", K::label},   {"box", K::box},
                                                    {"sphere", K::sphere}, {"halfspace", K::halfspace},
                                                    {"tets", K::tets}};
  bool found = false;
  for (const auto& [name, k] : kinds)
    if (kind == name) s.kind = k, found = true;
  if (!found) fail("unknown region kind '", kind, "'");
  read_shape_fields(L, idx, s);
  return s;
}

std::string describe_selection(lua_State* L, int idx) {
  idx = lua_absindex(L, idx);
  const std::string kind = get_string(L, idx, "kind");
  auto v = [&](const char* k) {
    const Eigen::Vector3d x = get_vec3(L, idx, k, Eigen::Vector3d::Zero());
    return cat("{", x(0), ", ", x(1), ", ", x(2), "}");
  };
  if (kind == "sphere") return cat("sphere center ", v("center"), " radius ", get_number(L, idx, "radius", 0), " m");
  if (kind == "box") return cat("box ", v("min"), " .. ", v("max"), " m");
  if (kind == "halfspace") return cat("half-space through ", v("point"), " normal ", v("normal"));
  if (kind == "label") return cat("label ", get_int(L, idx, "label", -1));
  if (kind == "surface") {
    const int l = get_int(L, idx, "label", -1);
    return l < 0 ? std::string("the surface") : cat("the surface of label ", l);
  }
  if (kind == "nodes") return cat(get_ints(L, idx, "ids").size(), " listed nodes");
  if (kind == "tets") return cat(get_ints(L, idx, "ids").size(), " listed tets");
  if (kind == "named") return cat("node set '", get_string(L, idx, "name"), "'");
  if (kind == "union_of") return "the union";
  if (kind == "intersection") return "the intersection";
  if (kind == "difference") return "the difference";
  return kind;
}

}  // namespace softcut::lua
