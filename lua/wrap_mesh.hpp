#pragma once
// The mesh a scenario loaded at s:mesh{} (Lua userdata "softcut.MeshHandle"):
// kept so selections are evaluated, and refused when empty, at their line.
#include <string>
#include <vector>

#include "mesh/surface.hpp"
#include "sim/mesh_source.hpp"
#include "sim/selector.hpp"

struct lua_State;

namespace softcut::lua {

struct MeshHandle {
  sim::MeshSource source;     // as given (file made absolute); handed on to the ScenarioSpec
  sim::LoadedMesh loaded;     // rest mesh and named node sets
  mesh::Surface surface;      // whole-body boundary
  std::vector<std::string> warnings;  // from loading (validate)
  std::size_t charged = 0;            // bytes counted against the sandbox's memory budget
  sim::SelectContext context() const;
  std::size_t bytes() const;          // memory held, bytes (estimate: the big arrays)
};

// The handle at `idx`, or nullptr when it is not one.
MeshHandle* to_mesh_handle(lua_State* L, int idx);
void register_mesh_meta(lua_State* L);

}  // namespace softcut::lua
