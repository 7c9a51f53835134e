// lua/wrap_mesh.cpp: s:mesh{} info and selections evaluated on the mesh.
#include <doctest/doctest.h>

#include "lua_test_support.hpp"
#include "mesh/generate/box.hpp"
#include "mesh/io/mesh_io.hpp"

using softcut::test::contains;
using softcut::test::scenario_error;
using softcut::test::write_scenario;

namespace {

// Runs `body` after a 4x3x2 unit-cell box mesh (5*4*3 = 60 nodes); the body
// asserts in Lua. Returns the error or "".
std::string with_box(const std::string& body) {
  const std::string head = R"(
local s = softcut.scenario{ duration = 0 }
local m = s:mesh{ generate = "box", options = { min = {0, 0, 0}, max = {4, 3, 2}, nx = 4, ny = 3, nz = 2, label = 5 } }
local S = softcut.select
local function n(sel) return #s:select(sel) end
)";
  const auto f = write_scenario("wrap_mesh", head + body + "\nerror('done')\n", "mesh.lua");
  const std::string e = scenario_error(f);
  return contains(e, "done") ? "" : e;
}

}  // namespace

TEST_SUITE("lua/wrap_mesh") {
  TEST_CASE("mesh info: counts, labels, bounds") {
    CHECK(with_box(R"(
assert(m.num_nodes == 60 and m.num_tets == 4 * 3 * 2 * 6, m.num_nodes .. " " .. m.num_tets)
assert(#m.labels == 1 and m.labels[1] == 5)
assert(m.min[1] == 0 and m.max[1] == 4 and m.max[2] == 3 and m.max[3] == 2)
assert(m.center[1] == 2 and m.size[3] == 2)
assert(#m.surface_nodes == 60 - 3 * 2 * 1)
)") == "");
  }

  TEST_CASE("selections against independent counts on the grid") {
    CHECK(with_box(R"(
assert(n(S.all()) == 60)
assert(n(S.label(5)) == 60)
assert(n(S.surface()) == 60 - 3 * 2 * 1)                               -- all minus interior (nx-1)(ny-1)(nz-1)
local x0 = S.box{ min = {0, 0, 0}, max = {0, 3, 2} }
local x4 = S.box{ min = {4, 0, 0}, max = {4, 3, 2} }
local y0 = S.halfspace{ point = {0, 0, 0}, normal = {0, -1, 0} }
assert(n(x0) == 4 * 3)                                                   -- (ny+1)(nz+1)
assert(n(x0 + x4) == 2 * 4 * 3)
assert(n(x0 * y0) == 3)                                                  -- an edge: nz+1
assert(n(S.all() - S.surface()) == 3 * 2 * 1)
assert(n(x0:union(x4):difference(y0)) == 2 * 4 * 3 - 2 * 3)
assert(n(S.sphere{ center = {2, 1, 1}, radius = 1.01 }) == 7)           -- center and its 6 neighbours
assert(n(S.nodes{ 0, 59, 59 }) == 2)
local ids = s:select(S.nodes{ 7, 3 })
assert(ids[1] == 3 and ids[2] == 7)                                      -- sorted, 0-based
)") == "");
  }

  TEST_CASE("an empty selection is an error at the line that uses it") {
    const std::string e = with_box("local far = S.sphere{ center = {10, 10, 10}, radius = 1 }\ns:fix{ nodes = far }");
    CHECK(contains(e, "mesh.lua:7: fix: the selection is empty: sphere center {10, 10, 10} radius 1 m selects no node"));
    CHECK(contains(e, "60 nodes, bounds {0, 0, 0} .. {4, 3, 2}"));
  }

  TEST_CASE("unknown labels, node ids and named sets are errors naming them") {
    CHECK(contains(with_box("s:material{ label = 2, tissue = 'fat' }"), "mesh.lua:6: material: unknown label 2 (the mesh has labels 5)"));
    CHECK(contains(with_box("s:fix{ nodes = S.label(9) }"), "fix: no tet has label 9"));
    CHECK(contains(with_box("s:fix{ nodes = S.nodes{ 60 } }"), "fix: node id 60 (entry 1) is out of range"));
    CHECK(contains(with_box("s:fix{ nodes = S.named('hole') }"), "fix: no node set named 'hole'"));
    CHECK(contains(with_box("s:operational{ sphere = { center = {9, 9, 9}, radius = 0.1 } }"),
                   "mesh.lua:6: operational: region is empty"));
  }

  TEST_CASE("mesh sources: file relative to the scenario, named sets of generators, errors") {
    const auto f = write_scenario("wrap_mesh_file", R"(
local s = softcut.scenario{ duration = 0 }
local m = s:mesh{ file = "missing.msh" }
)");
    CHECK(contains(scenario_error(f), "scenario.lua:3: mesh: file 'missing.msh' not found"));
    const auto out = write_scenario("wrap_mesh_outside", R"(
local s = softcut.scenario{ duration = 0 }
local m = s:mesh{ file = "../../../etc/passwd" }
)");
    CHECK(contains(scenario_error(out), "scenario.lua:3: mesh: file '../../../etc/passwd' is outside the scenario's folder"));
    const auto g = write_scenario("wrap_mesh_gen", R"(
local s = softcut.scenario{ duration = 0 }
local m = s:mesh{ generate = "upper_leg" }
assert(m.sets[1] == "hole", tostring(m.sets[1]))
assert(#s:select(softcut.select.named("hole")) > 0)
s:mesh{ generate = "box" }
)");
    CHECK(contains(scenario_error(g), "scenario.lua:6: mesh: the scenario already has a mesh"));
    const auto h = write_scenario("wrap_mesh_opt", R"(
local s = softcut.scenario{ duration = 0 }
s:mesh{ generate = "box", options = { nxx = 3 } }
)");
    CHECK(contains(scenario_error(h), "scenario.lua:3: mesh"));
    CHECK(contains(scenario_error(h), "unknown option 'nxx'"));
    const auto k = write_scenario("wrap_mesh_order", "local s = softcut.scenario{ duration = 0 }\ns:fix{ nodes = softcut.select.all() }\n");
    CHECK(contains(scenario_error(k), "scenario.lua:2: fix: call s:mesh{...} first"));
  }
}

TEST_SUITE("lua/wrap_mesh") {
  TEST_CASE("s:mesh{ file = ..., unit, scale }, and generate = \"surface\" with options.file and options.unit") {
    const auto dir = softcut::test::scratch_dir("wrap_mesh_units");
    // A mesh file in millimetres (a 100 x 40 x 40 mm box).
    const auto make = write_scenario("wrap_mesh_units", R"(
local s = softcut.scenario{ duration = 0 }
local m = s:mesh{ file = "box_mm.msh", unit = "mm" }
assert(math.abs(m.size[1] - 0.1) < 1e-12, m.size[1])
local n = s:mesh{ file = "box_mm.msh", scale = 0.5 }
)");
    softcut::mesh::BoxOptions b;
    b.max_corner = Eigen::Vector3d(100, 40, 40);
    softcut::mesh::write_mesh(dir / "box_mm.msh", softcut::mesh::generate_box(b));
    CHECK(contains(scenario_error(make), "scenario.lua:5: mesh: the scenario already has a mesh"));
    const auto bad_unit = write_scenario("wrap_mesh_units", "local s = softcut.scenario{ duration = 0 }\ns:mesh{ file = \"box_mm.msh\", unit = \"inch\" }\n",
                                         "bad_unit.lua");
    CHECK(contains(scenario_error(bad_unit), "bad_unit.lua:2: mesh: field 'unit': unknown value 'inch'"));
    // Surfaces below the scenario's folder, the organ first (copied after
    // write_scenario, which empties the folder).
    const auto surf = write_scenario("wrap_mesh_units", R"(
local s = softcut.scenario{ duration = 0 }
local m = s:mesh{ generate = "surface", options = { file = { "outer_mm.off", "inner_mm.obj" }, unit = "mm", target_tets = 1500 } }
assert(#m.labels == 2 and m.labels[2] == 2, #m.labels)
assert(math.abs(m.size[1] - 0.08) < 0.002, m.size[1])  -- an 80 mm sphere, in metres
error("done")
)", "surface.lua");
    for (const char* f : {"outer_mm.off", "inner_mm.obj"})
      std::filesystem::copy_file(softcut::test::data_dir() / "surface" / f, dir / f,
                                 std::filesystem::copy_options::overwrite_existing);
    CHECK(contains(scenario_error(surf), "surface.lua:6: done"));
    const auto outside = write_scenario("wrap_mesh_units", R"(
local s = softcut.scenario{ duration = 0 }
s:mesh{ generate = "surface", options = { file = "../x.stl" } }
)", "outside.lua");
    CHECK(contains(scenario_error(outside), "outside.lua:3: mesh: surface file '../x.stl' is outside the scenario's folder"));
    const auto misplaced = write_scenario("wrap_mesh_units", R"(
local s = softcut.scenario{ duration = 0 }
s:mesh{ generate = "box", options = { file = "outer_mm.off" } }
)", "misplaced.lua");
    CHECK(contains(scenario_error(misplaced), "options.file and options.unit are the surface generator's"));
  }
}
