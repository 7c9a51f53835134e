// Mesh bindings: load the rest mesh at s:mesh{} and evaluate selections on it.
#include <algorithm>
#include <filesystem>
#include <set>

#include "bindings.hpp"
#include "core/checked_file.hpp"
#include "core/printable.hpp"
#include "convert.hpp"
#include "mesh/surface.hpp"
#include "runtime.hpp"
#include "sandbox/limits.hpp"
#include "sim/mesh_source.hpp"
#include "sim/selector.hpp"
#include "wrap_mesh.hpp"

namespace fs = std::filesystem;

namespace softcut::lua {

namespace {

const char* kMeshMeta = "softcut.MeshHandle";

// Native work charged to the sandbox's instruction budget, in Lua
// instructions per item: loading (generate or read, validate, extract the
// surface) costs ~0.6 us per tet, a selection ~20-50 ns per node or tet, and
// a Lua instruction ~10 ns.
constexpr double kLoadInstructionsPerTet = 50;
constexpr double kSelectInstructionsPerItem = 4;

MeshHandle& check_handle(lua_State* L, int idx) {
  MeshHandle* h = *static_cast<MeshHandle**>(luaL_checkudata(L, idx, kMeshMeta));
  if (!h) fail("mesh: this mesh handle was released (a handle kept alive past its collection)");
  return *h;
}

int handle_gc(lua_State* L) {
  auto** p = static_cast<MeshHandle**>(luaL_checkudata(L, 1, kMeshMeta));
  if (*p) release_memory(L, (*p)->charged);
  delete *p;
  *p = nullptr;
  return 0;
}

// Generator options: numbers, or 3-vectors flattened to name.x/.y/.z; the
// surface generator's `file` (a name or a list of names) and `unit` go to
// `files` and `unit`.
std::map<std::string, double> read_options(lua_State* L, int idx, std::vector<std::string>& files, std::string& unit) {
  std::map<std::string, double> out;
  if (lua_isnil(L, idx)) return out;
  if (!lua_istable(L, idx)) fail("mesh: options must be a table of named numbers");
  idx = lua_absindex(L, idx);
  lua_pushnil(L);
  long long keys = 0;
  while (lua_next(L, idx)) {
    // Each key is read, copied into a map (and again by compile): ~2 us, so
    // charged like a few hundred instructions.
    if (++keys % 1024 == 0) charge_work(L, 256.0 * 1024, "mesh options");
    if (lua_type(L, -2) != LUA_TSTRING) {
      lua_pop(L, 2);
      fail("mesh: options must be named (name = value)");
    }
    const std::string key = lua_tostring(L, -2);
    if (key == "unit" && lua_type(L, -1) == LUA_TSTRING) {
      unit = lua_tostring(L, -1);
    } else if (key == "file" && lua_type(L, -1) == LUA_TSTRING) {
      files.push_back(lua_tostring(L, -1));
    } else if (key == "file" && lua_istable(L, -1)) {
      const lua_Unsigned n = lua_rawlen(L, -1);  // raw: no __len of the script's runs here
      if (n == 0 || n > 64) {
        lua_pop(L, 2);
        fail("mesh: options.file must name 1 to 64 surface files, got a list of ", n);
      }
      for (lua_Unsigned i = 1; i <= n; ++i) {
        if (lua_rawgeti(L, -1, lua_Integer(i)) != LUA_TSTRING) {
          lua_pop(L, 3);
          fail("mesh: options.file[", i, "] must be a file name");
        }
        files.push_back(lua_tostring(L, -1));
        lua_pop(L, 1);
      }
    } else if (key == "file" || key == "unit") {
      const std::string t = luaL_typename(L, -1);
      lua_pop(L, 2);
      fail("mesh: option '", key, "' must be ", key == "file" ? "a file name or a list of them" : "a unit name", ", got ", t);
    } else if (lua_type(L, -1) == LUA_TNUMBER) {
      out[key] = lua_tonumber(L, -1);
    } else if (lua_istable(L, -1)) {
      Eigen::Vector3d v;
      try {
        v = to_vec3(L, -1);
      } catch (const Error&) {
        lua_pop(L, 2);
        fail("mesh: option '", key, "' must be a number or a 3-vector {x, y, z}");
      }
      out[key + ".x"] = v(0), out[key + ".y"] = v(1), out[key + ".z"] = v(2);
    } else {
      const std::string t = luaL_typename(L, -1);
      lua_pop(L, 2);
      fail("mesh: option '", key, "' must be a number or a 3-vector {x, y, z}, got ", t);
    }
    lua_pop(L, 1);
  }
  return out;
}

// mesh_load(args, scenario_dir) -> handle, info | nil, message
int mesh_load(lua_State* L) {
  return protect(L, [L] {
    luaL_checktype(L, 1, LUA_TTABLE);
    luaL_checkstring(L, 2);
    // The userdata comes first, while no C++ object is alive: a Lua error
    // (out of memory) raised here skips no destructor, and later the
    // userdata owns the mesh. __gc gives back what the handle was charged.
    auto** ud = static_cast<MeshHandle**>(lua_newuserdatauv(L, sizeof(MeshHandle*), 0));
    *ud = nullptr;
    luaL_setmetatable(L, kMeshMeta);
    const fs::path dir = lua_tostring(L, 2);
    auto h = std::make_unique<MeshHandle>();
    h->source.where = user_where(L);
    // A file the script names, relative to its folder: checked as the sandbox
    // reads (below the folder, through the checked open; a link on the way is
    // refused whether or not its target exists: fs::exists would follow it
    // and tell the script which outside files exist).
    const auto locate = [&](const std::string& name, const char* what) {
      const fs::path path = fs::absolute(dir / name).lexically_normal();
      if (!may_read(L, path))
        fail(h->source.where, ": mesh: ", what, " '", printable(name), "' is outside the scenario's folder ",
             printable(dir.string()), " (the sandbox reads only below it; run with --trust to lift this)");
      bool found = false;
      if (options_of(L).trusted) {
        found = fs::exists(path);
      } else {
        int missing = 0;
        found = bool(open_below_if_exists(options_of(L).read_dir, relative_below(options_of(L).read_dir, path),
                                          Access::read, h->source.where + ": mesh", &missing));
      }
      if (!found)
        fail(h->source.where, ": mesh: ", what, " '", printable(name), "' not found (looked for ", printable(path.string()),
             "; paths are relative to the scenario's folder)");
      return path;
    };
    const std::string file = get_string(L, 1, "file");
    h->source.generator = get_string(L, 1, "generate");
    h->source.unit = get_string(L, 1, "unit");
    h->source.scale = get_number(L, 1, "scale", 1.0);
    std::vector<std::string> surfaces;
    std::string surface_unit;
    lua_pushliteral(L, "options");
    lua_rawget(L, 1);  // raw: no __index of the script's runs here
    h->source.options = read_options(L, -1, surfaces, surface_unit);
    lua_pop(L, 1);
    if ((!surfaces.empty() || !surface_unit.empty()) && h->source.generator != "surface")
      fail(h->source.where, ": mesh: options.file and options.unit are the surface generator's (generate = \"surface\"); "
           "a mesh file is s:mesh{ file = ..., unit = ... }");
    if (h->source.generator == "surface") {
      if (!h->source.unit.empty())
        fail(h->source.where, ": mesh: give the surfaces' unit in options (options = { file = ..., unit = \"",
             printable(h->source.unit), "\" })");
      h->source.unit = surface_unit;
    }
    if (!file.empty()) h->source.file = locate(file, "file");
    for (const auto& f : surfaces) h->source.surfaces.push_back(locate(f, "surface file"));
    Diagnostics diag;
    // The file (and a TetGen sibling) through the checked open below the
    // scenario folder; decoded data within what is left of the memory budget.
    mesh::ReadOptions read;
    if (!options_of(L).trusted) {
      const Runtime::Budget* b = budget_of(L);
      read.root = options_of(L).read_dir;
      if (b->limit) read.max_bytes = b->limit - std::min(b->limit, b->used + b->native);
    }
    {
      // Bounded by the mesh size limit (and charged below), not by the
      // call's CPU time: meshing a 2M-tet organ takes ~30 s. CGAL meshing
      // stops at the run's deadline too.
      const CpuExempt exempt(L);
      h->source.stop = options_of(L).deadline;
      h->loaded = sim::load_mesh_source(h->source, diag, max_tets(L), read);
      h->surface = mesh::extract_surface(h->loaded.mesh);
    }
    h->warnings = diag.warnings;
    const mesh::TetMesh& m = h->loaded.mesh;
    charge_work(L, kLoadInstructionsPerTet * m.num_tets(), "mesh");
    const std::size_t bytes = h->bytes();
    charge_memory(L, bytes, h->source.where + ": mesh");
    h->charged = bytes;
    *ud = h.release();

    lua_newtable(L);
    lua_pushinteger(L, m.num_nodes());
    lua_setfield(L, -2, "num_nodes");
    lua_pushinteger(L, m.num_tets());
    lua_setfield(L, -2, "num_tets");
    std::set<int> labels(m.labels.data(), m.labels.data() + m.labels.size());
    push_ints(L, std::vector<int>(labels.begin(), labels.end()));
    lua_setfield(L, -2, "labels");
    const Eigen::Vector3d lo = m.num_nodes() ? Eigen::Vector3d(m.nodes.colwise().minCoeff()) : Eigen::Vector3d::Zero();
    const Eigen::Vector3d hi = m.num_nodes() ? Eigen::Vector3d(m.nodes.colwise().maxCoeff()) : Eigen::Vector3d::Zero();
    push_vec3(L, lo);
    lua_setfield(L, -2, "min");
    push_vec3(L, hi);
    lua_setfield(L, -2, "max");
    push_vec3(L, 0.5 * (lo + hi));
    lua_setfield(L, -2, "center");
    push_vec3(L, hi - lo);
    lua_setfield(L, -2, "size");
    lua_newtable(L);
    int k = 1;
    for (const auto& [name, ids] : (*ud)->loaded.named_sets) {
      lua_pushstring(L, name.c_str());
      lua_rawseti(L, -2, k++);
    }
    lua_setfield(L, -2, "sets");
    push_ints(L, (*ud)->surface.nodes);
    lua_setfield(L, -2, "surface_nodes");
    if (!file.empty()) {
      lua_pushstring(L, (*ud)->source.file.c_str());
      lua_setfield(L, -2, "file");
    }
    return 2;
  });
}

// select_nodes(handle, selection, fname) -> ids (0-based, sorted) | nil, message
int select_nodes(lua_State* L) {
  return protect(L, [L] {
    MeshHandle& h = check_handle(L, 1);
    const sim::NodeSelector sel = to_node_selector(L, 2);
    const std::string fname = luaL_optstring(L, 3, "select");
    charge_work(L, kSelectInstructionsPerItem * h.loaded.mesh.num_nodes() * selection_parts(sel),
                fname);
    try {
      push_ints(L, sim::select_nodes(sel, h.context(), fname));
      return 1;
    } catch (const Error& e) {
      lua_pushnil(L);
      lua_pushstring(L, e.what());
      return 2;
    }
  });
}

// count_tets(handle, region, fname) -> n | nil, message
int count_tets(lua_State* L) {
  return protect(L, [L] {
    MeshHandle& h = check_handle(L, 1);
    const sim::TetSelector sel = to_tet_selector(L, 2);
    const std::string fname = luaL_optstring(L, 3, "region");
    charge_work(L, kSelectInstructionsPerItem * h.loaded.mesh.num_tets(), fname);
    try {
      lua_pushinteger(L, lua_Integer(sim::select_tets(sel, h.context(), fname).size()));
      return 1;
    } catch (const Error& e) {
      lua_pushnil(L);
      lua_pushstring(L, e.what());
      return 2;
    }
  });
}

// check_on_surface(handle, ids) -> nil | message naming the first interior node
int check_on_surface(lua_State* L) {
  return protect(L, [L] {
    MeshHandle& h = check_handle(L, 1);
    lua_newtable(L);
    lua_pushvalue(L, 2);
    lua_setfield(L, -2, "ids");
    const std::vector<int> ids = get_ints(L, -1, "ids");
    lua_pop(L, 1);
    int off = 0, first = -1;
    for (int n : ids)
      if (!std::binary_search(h.surface.nodes.begin(), h.surface.nodes.end(), n)) {
        if (first < 0) first = n;
        ++off;
      }
    if (off == 0) return 0;
    const std::string msg = cat(off, " of ", ids.size(), " selected nodes are not on the surface (first: node ", first,
                                "); intersect with softcut.select.surface()");
    lua_pushlstring(L, msg.data(), msg.size());
    return 1;
  });
}

int describe(lua_State* L) {
  return protect(L, [L] {
    const std::string s = describe_selection(L, 1);
    lua_pushlstring(L, s.data(), s.size());
    return 1;
  });
}

int format_vec(lua_State* L) {
  return protect(L, [L] {
    const Eigen::Vector3d v = to_vec3(L, 1);
    const std::string s = cat("{", v(0), ", ", v(1), ", ", v(2), "}");
    lua_pushlstring(L, s.data(), s.size());
    return 1;
  });
}

}  // namespace

sim::SelectContext MeshHandle::context() const { return {loaded.mesh, surface, loaded.named_sets}; }

std::size_t MeshHandle::bytes() const {
  const mesh::TetMesh& m = loaded.mesh;
  std::size_t n = sizeof(MeshHandle) + sizeof(double) * m.nodes.size() + sizeof(int) * (m.tets.size() + m.labels.size()) +
                  sizeof(int) * (surface.faces.size() + surface.face_tet.size() + surface.nodes.size());
  for (const auto& [name, ids] : loaded.named_sets) n += name.size() + sizeof(int) * ids.size();
  return n;
}

MeshHandle* to_mesh_handle(lua_State* L, int idx) {
  void* p = luaL_testudata(L, idx, kMeshMeta);
  return p ? *static_cast<MeshHandle**>(p) : nullptr;
}

void register_mesh_meta(lua_State* L) {
  if (luaL_newmetatable(L, kMeshMeta)) {
    lua_pushcfunction(L, handle_gc);
    lua_setfield(L, -2, "__gc");
    lua_pushboolean(L, 0);  // locked: getmetatable(handle) is false, its __gc stays ours
    lua_setfield(L, -2, "__metatable");
  }
  lua_pop(L, 1);
}

const luaL_Reg kMeshFunctions[] = {
    {"mesh_load", mesh_load},           {"select_nodes", select_nodes},
    {"count_tets", count_tets},         {"check_on_surface", check_on_surface},
    {"describe_selection", describe},   {"format_vec", format_vec},
    {nullptr, nullptr}};

}  // namespace softcut::lua
