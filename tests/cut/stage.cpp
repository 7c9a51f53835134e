// The cutting stage (cut/stage.hpp) driven directly, without a Model or a
// solver: a scalpel held by hand across a bar fixed at one end. What the run
// state must look like after it cuts (events, grown fields, the piece cut
// free held, one rebuild) and what it refuses.
#include "cut/stage.hpp"

#include <doctest/doctest.h>

#include "mesh/generate/box.hpp"
#include "mesh/surface.hpp"
#include "test_support.hpp"

using namespace softcut;
using V = Eigen::Vector3d;

namespace {

// A 0.1 x 0.04 x 0.04 m bar (5 x 2 x 2 cells, all operational), fixed at x = 0,
// and one scalpel whose edge crosses the bar's section at x = 0.05.
struct Bench {
  mesh::TetMesh mesh;
  mesh::Surface surface;
  std::vector<fem::Material> material;
  std::vector<char> operational;
  std::vector<int> fixed, interface;
  std::unique_ptr<cut::CutMesh> cm;
  std::vector<tools::ToolSpec> specs{1};
  std::vector<tools::ToolState> tools{1};
  Eigen::MatrixX3d u, f;
  std::vector<std::string> warnings;
  int rebuilds = 0;

  Bench() {
    mesh::BoxOptions o;
    o.max_corner = V(0.1, 0.04, 0.04);
    o.nx = 5, o.ny = 2, o.nz = 2;
    mesh = mesh::generate_box(o);
    surface = mesh::extract_surface(mesh);
    material.assign(size_t(mesh.num_tets()), fem::Material{});
    operational.assign(size_t(mesh.num_tets()), 1);
    for (int n = 0; n < mesh.num_nodes(); ++n)
      if (mesh.nodes(n, 0) == 0) fixed.push_back(n);
    u = Eigen::MatrixX3d::Zero(mesh.num_nodes(), 3);
    f = Eigen::MatrixX3d::Ones(mesh.num_nodes(), 3);
    tools::ToolSpec& s = specs[0];
    s.name = "blade";
    s.kind = tools::ToolSpec::Kind::scalpel;
    s.cut_pressure = 100;
    tools::ToolState& t = tools[0];
    t.override_tip = true;  // held by hand: no path to trace back
    t.engaged = true;
    t.pressure = 1000;      // pressing at 10x its cut_pressure
    // The edge spans the section in z and sweeps across it in y, at x = 0.05.
    t.prev_a = V(0.05, -0.01, 0.06), t.prev_b = V(0.05, -0.01, -0.02);
    t.blade_a = V(0.05, 0.05, 0.06), t.blade_b = V(0.05, 0.05, -0.02);
    t.has_prev = true;
  }
  cut::RestBody rest() const { return {mesh, surface, material, operational, fixed, interface}; }
  std::vector<cut::CutEvent> run(double t = 0.1) {
    cut::StageFrame fr{.frame = 3, .t = t, .t_prev = t - 0.1, .dt = 0.1, .options = {}, .cut = cm, .specs = specs,
                       .tools = tools, .displacement = u, .forces = f, .warnings = warnings,
                       .cg_iterations_before = 17,
                       .rebuild = [this](const cut::CutMesh&, const cut::CutRecord&) { ++rebuilds; }};
    return cut::cut_stage(rest(), fr);
  }
};

}  // namespace

TEST_SUITE("cut/stage") {
  TEST_CASE("a pressing blade across the section cuts the bar in two: one event, grown fields, the free end held") {
    Bench b;
    const int nodes0 = b.mesh.num_nodes();
    const std::vector<cut::CutEvent> ev = b.run();
    REQUIRE(ev.size() == 1);
    CHECK(ev[0].frame == 3);
    CHECK(ev[0].tool == "blade");
    CHECK(ev[0].tets_split > 0);
    CHECK(ev[0].nodes_added > 0);
    CHECK(ev[0].cg_iterations_before == 17);
    CHECK(ev[0].pieces_freed == 1);  // x > 0.05 holds no fixed node
    REQUIRE(b.cm);
    CHECK(b.rebuilds == 1);
    CHECK(b.cm->mesh.num_nodes() == nodes0 + ev[0].nodes_added);
    CHECK(ev[0].nodes_after == b.cm->mesh.num_nodes());
    CHECK(b.u.rows() == b.cm->mesh.num_nodes());
    REQUIRE(b.f.rows() == b.cm->mesh.num_nodes());
    CHECK(b.f.topRows(nodes0).isOnes());             // the frame's forces are kept ...
    CHECK(b.f.bottomRows(ev[0].nodes_added).isZero());  // ... and new nodes start with none
    CHECK(cut::count_components(b.cm->mesh) == 2);
    // The free end is held; the fixed end is not.
    int held = 0;
    for (int n = 0; n < b.cm->mesh.num_nodes(); ++n) {
      const bool right = b.cm->mesh.nodes(n, 0) > 0.05 + 1e-9;
      if (right) CHECK(cut::is_held(*b.cm, n));
      if (b.cm->mesh.nodes(n, 0) < 0.05 - 1e-9) CHECK_FALSE(cut::is_held(*b.cm, n));
      held += cut::is_held(*b.cm, n);
    }
    CHECK(cut::detached_counts(*b.cm).nodes == held);
    CHECK(b.tools[0].cutting);
    CHECK(b.tools[0].cut_events == 1);
    REQUIRE(!b.warnings.empty());
    CHECK(test::contains(b.warnings.back(), "frame 3 (t = 0.1 s), scalpel 'blade': piece of "));
    const cut::CuttingSummary s = cut::cutting_summary(b.cm->mesh, b.cm.get(), ev);
    CHECK(s.events == 1);
    CHECK(s.components == 2);
    CHECK(s.detached == 1);
  }

  TEST_CASE("a blade that does not press, is not active, or is not a scalpel leaves everything as it was") {
    for (int k = 0; k < 3; ++k) {
      CAPTURE(k);
      Bench b;
      if (k == 0) b.tools[0].pressure = 99;  // below cut_pressure
      if (k == 1) b.specs[0].stop = 0.05;
      if (k == 2) b.specs[0].kind = tools::ToolSpec::Kind::probe;
      // Outside the bar, so a blade that does not cut is not refused either.
      b.tools[0].blade_a = V(0.05, 0.05, 0.06), b.tools[0].blade_b = V(0.05, 0.05, 0.05);
      CHECK(b.run().empty());
      CHECK_FALSE(b.cm);
      CHECK(b.rebuilds == 0);
      CHECK(b.u.rows() == b.mesh.num_nodes());
      CHECK(b.warnings.empty());
    }
  }

  TEST_CASE("refused: a non-finite blade, and a blade inside the tissue that is not cutting") {
    Bench b;
    b.tools[0].blade_a.x() = std::nan("");
    CHECK(test::contains(test::error_of([&] { b.run(); }), "scalpel 'blade': blade position is not finite at t = 0.1 s"));
    Bench c;
    c.tools[0].pressure = 0;
    c.tools[0].engaged = false;
    c.tools[0].blade_a = V(0.05, 0.02, 0.03), c.tools[0].blade_b = V(0.05, 0.02, 0.01);  // inside the bar
    const std::string e = test::error_of([&] { c.run(); });
    CHECK(test::contains(e, "mm inside the tissue"));
    CHECK(test::contains(e, "but it is not cutting"));
    CHECK_FALSE(c.cm);
  }
}
