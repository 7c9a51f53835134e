#include "sim/cutting.hpp"

#include <doctest/doctest.h>

#include <fstream>
#include <random>
#include <sstream>

#include "fem/whole_mesh.hpp"
#include "sim/frame_scene.hpp"
#include "sim/model.hpp"
#include "sim/outputs.hpp"
#include "sim/run.hpp"
#include "sim/step.hpp"
#include "fixtures.hpp"
#include "test_support.hpp"

using V = Eigen::Vector3d;
namespace sim = softcut::sim;
namespace tools = softcut::tools;

using softcut::test::slurp;

namespace {

// A 0.1 x 0.02 x 0.02 m bar (10 x 4 x 4 cells) fixed at both ends, pressed
// down on its top by a distributed load, with an operational slab across the
// whole section in the middle. A scalpel (40 mm edge along y, wider than the
// bar) presses the top at x = 0.0512, then goes down through the bar: a
// through-cut leaves two pieces, each fixed at its end.
sim::ScenarioSpec bar_cut_spec(const std::string& name, double cut_pressure, const std::string& backend = "cpu") {
  sim::ScenarioSpec s = softcut::test::held_bar_spec(name, V(0.1, 0.02, 0.02), 5e3, 0.03, 0.07, true);
  sim::LoadSpec top;
  top.name = "top";
  top.nodes = sim::NodeSelector::box(V(0.015, -1, 0.02), V(0.085, 1, 1));
  top.direction = V(0, 0, -1);
  top.magnitude = tools::Ramp::linear_ramp(0.0, 0.01, 0.0, 0.2);
  s.loads.push_back(top);
  s.tools.push_back(softcut::test::through_cut_blade(cut_pressure));
  s.timeline.duration = 1.0;
  s.timeline.fps = 20.0;
  s.outputs.dir = softcut::test::scratch_dir(name);
  s.solver.backend = softcut::backend::parse_backend(backend);
  s.solver.cg_tolerance = 1e-12;
  return s;
}

// A bar 0.1 x 0.04 x 0.04 m (10 x 4 x 4 cells) held at both ends, operational
// between x = 0.01 and 0.09; a vertical scalpel (60 mm edge along z) follows a
// Z-shaped path in the mid-plane: across y to y1 at x = xa, diagonally to y2
// at x = xb, then on to y_end. With a load, the top near one end moves the
// tissue while the blade passes (4 mN, oscillating at 3 Hz).
sim::ScenarioSpec zigzag_spec(const std::string& name, double xa, double xb, double y1, double y2, double y_end,
                              double fps, bool moving) {
  sim::ScenarioSpec s = softcut::test::held_bar_spec(name, V(0.1, 0.04, 0.04), 5e3, 0.01, 0.09, true);
  if (moving)
    s.loads.push_back(softcut::test::wobble_load(sim::NodeSelector::box(V(0.021, -1, 0.04), V(0.039, 1, 1)), V(0, 0, -1)));
  tools::ToolSpec blade = softcut::test::cutting_blade(V(0, 0, 1), V(0, 1, 0));
  blade.path = tools::Path::polyline({0.1, 0.35, 0.6, 0.85}, {V(xa, -0.0005, 0.02), V(xa, y1, 0.02),
                                                                V(xb, y2, 0.02), V(xb, y_end, 0.02)});
  s.tools.push_back(blade);
  s.timeline.duration = 1.0;
  s.timeline.fps = fps;
  s.outputs.dir = softcut::test::scratch_dir(name);
  s.outputs.csv = false;
  s.solver.backend = softcut::backend::Backend::direct;
  return s;
}

void run_all(const sim::Model& m, sim::State& s) {
  while (s.frame < m.num_frames - 1) sim::step(m, s);
}

}  // namespace

TEST_SUITE("sim/cutting") {
  TEST_CASE("random Z-shaped blade paths on still and moving tissue: a path across the section separates, one that stops short does not") {
    // Issue #16 items 1 and 2: before the fixes 21 of 60 such through-paths on
    // still tissue left the bar in one piece (a column of un-cut faces at a
    // corner), and moving tissue was not cut through.
    std::mt19937 rng(16);
    auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
    const double fps_choices[] = {30, 37, 40, 50, 60};
    int through_cases = 0, short_cases = 0;
    for (int k = 0; k < 24; ++k) {
      const double xa = uniform(0.02, 0.05), xb = uniform(0.05, 0.08);
      const double y1 = uniform(0.005, 0.02), y2 = uniform(0.02, 0.035);
      const bool through = k % 3 != 2;
      const double y_end = through ? 0.045 : uniform(y2 + 0.001, 0.034);
      const double fps = fps_choices[std::uniform_int_distribution<int>(0, 4)(rng)];
      const bool moving = k % 2 == 1;
      INFO("case ", k, ": xa ", xa, " xb ", xb, " y1 ", y1, " y2 ", y2, " y_end ", y_end, " fps ", fps, " moving ", moving);
      const sim::Model m = sim::compile(zigzag_spec("cut_zigzag", xa, xb, y1, y2, y_end, fps, moving));
      sim::State s = sim::make_state(m);
      run_all(m, s);
      REQUIRE(s.cut);
      const sim::CuttingSummary cs = sim::cutting_summary(m, s);
      CHECK(cs.components == (through ? 2 : 1));
      CHECK(cs.pieces == (through ? 2 : 1));
      CHECK(cs.detached == 0);  // each piece keeps a fixed end
      (through ? through_cases : short_cases)++;
    }
    CHECK(through_cases == 16);
    CHECK(short_cases == 8);
  }

  TEST_CASE("copy_state forks a run mid-cut: both continue to the same displacements, and neither sees the other") {
    for (const std::string backend : {"direct", "cpu", "monolithic"}) {
      CAPTURE(backend);
      const sim::Model m = sim::compile(bar_cut_spec("cut_copy_" + backend, 1000.0, backend));
      sim::State s = sim::make_state(m);
      while (s.cut_events.empty()) sim::step(m, s);  // the first cut has happened
      sim::State c = sim::copy_state(m, s);
      REQUIRE(c.cut);
      CHECK(c.cut.get() != s.cut.get());  // deep: its own cut mesh
      CHECK(c.frame == s.frame);
      CHECK(c.cut_events.size() == s.cut_events.size());
      // The original runs on alone for a while (cutting further), then both finish.
      for (int k = 0; k < 4; ++k) sim::step(m, s);
      CHECK(c.cut->mesh.num_tets() <= s.cut->mesh.num_tets());
      CHECK(c.frame == s.frame - 4);
      run_all(m, s);
      run_all(m, c);
      REQUIRE(c.displacement.rows() == s.displacement.rows());
      CHECK((c.cut->mesh.tets.array() == s.cut->mesh.tets.array()).all());
      const double scale = s.displacement.cwiseAbs().maxCoeff();
      REQUIRE(scale > 0);
      CHECK((c.displacement - s.displacement).cwiseAbs().maxCoeff() <= 1e-9 * scale);
      CHECK(c.cut_events.size() == s.cut_events.size());
    }
  }

  TEST_CASE("a through-cut splits the bar in two anchored pieces - hybrid equals whole-mesh solves of the cut mesh") {
    const sim::Model m = sim::compile(bar_cut_spec("cut_hybrid", 1000.0, "cpu"));
    const sim::Model mono = sim::compile(bar_cut_spec("cut_mono", 1000.0, "monolithic"));
    sim::State s = sim::make_state(m), t = sim::make_state(mono);
    int checked = 0;
    while (s.frame < m.num_frames - 1) {
      sim::step(m, s);
      sim::step(mono, t);
      REQUIRE(s.displacement.rows() == t.displacement.rows());
      if (!s.cut) continue;
      const sim::CutMesh& cm = *s.cut;
      // Same topology from both backends (the blade path and the fields agree).
      REQUIRE(t.cut);
      REQUIRE((cm.mesh.tets.array() == t.cut->mesh.tets.array()).all());
      // Hybrid vs monolithic backend vs an independent whole-mesh solve.
      const Eigen::MatrixX3d direct =
          softcut::fem::solve_whole_mesh(cm.mesh, cm.tet_material, cm.node_fixed, s.forces);
      const double scale = direct.cwiseAbs().maxCoeff();
      REQUIRE(scale > 0);
      double err_direct = 0, err_mono = 0;
      for (int n = 0; n < cm.mesh.num_nodes(); ++n) {
        if (sim::node_set(m, s, n) == softcut::hybrid::NodeSet::interior) continue;
        err_direct = std::max(err_direct, (s.displacement.row(n) - direct.row(n)).cwiseAbs().maxCoeff());
        err_mono = std::max(err_mono, (s.displacement.row(n) - t.displacement.row(n)).cwiseAbs().maxCoeff());
      }
      CHECK(err_direct <= 1e-8 * scale);
      CHECK(err_mono <= 1e-8 * scale);
      ++checked;
    }
    CHECK(checked > 3);
    REQUIRE(s.cut);
    CHECK(s.cut_events.size() >= 3);
    CHECK(softcut::cut::count_components(m.mesh) == 1);
    CHECK(softcut::cut::count_components(s.cut->mesh) == 2);
    const sim::CuttingSummary cs = sim::cutting_summary(m, s);
    CHECK(cs.events == int(s.cut_events.size()));
    CHECK(cs.components == 2);
    CHECK(cs.pieces == 2);
    CHECK(cs.detached == 0);  // each piece keeps its fixed end
    CHECK(cs.faces_separated > 0);
    CHECK(cs.tets == s.cut->mesh.num_tets());
    // Each piece keeps fixed nodes: nodes left of the cut move independently
    // of a load on the right piece only through nothing (no shared node).
    const sim::CutMesh& cm = *s.cut;
    for (int tet = 0; tet < cm.mesh.num_tets(); ++tet) {
      bool left = false, right = false;
      for (int k = 0; k < 4; ++k) (cm.mesh.nodes(cm.mesh.tets(tet, k), 0) < 0.0512 ? left : right) = true;
      if (left && right) {  // a tet straddling the cut plane must have been cut off on one side
        const V c = (cm.mesh.node(cm.mesh.tets(tet, 0)) + cm.mesh.node(cm.mesh.tets(tet, 1)) +
                     cm.mesh.node(cm.mesh.tets(tet, 2)) + cm.mesh.node(cm.mesh.tets(tet, 3))) / 4;
        CHECK(std::abs(c.x() - 0.0512) < 0.01);
      }
    }
  }

  TEST_CASE("cuts leave nonoperational tets, interface nodes and rest positions unchanged") {
    const sim::Model m = sim::compile(bar_cut_spec("cut_invariants", 1000.0));
    sim::State s = sim::make_state(m);
    run_all(m, s);
    REQUIRE(s.cut);
    const sim::CutMesh& cm = *s.cut;
    CHECK(cm.mesh.num_nodes() > m.mesh.num_nodes());
    CHECK((cm.mesh.nodes.topRows(m.mesh.num_nodes()).array() == m.mesh.nodes.array()).all());
    for (int t = 0; t < m.mesh.num_tets(); ++t)
      if (!m.partition.operational_tet[size_t(t)]) {
        CHECK((cm.mesh.tets.row(t).array() == m.mesh.tets.row(t).array()).all());
        CHECK(cm.operational_tet[size_t(t)] == 0);
      }
    for (int t = m.mesh.num_tets(); t < cm.mesh.num_tets(); ++t) CHECK(cm.operational_tet[size_t(t)] == 1);
    // No interface node was duplicated: no new node sits where an interface node is.
    for (int n = m.mesh.num_nodes(); n < cm.mesh.num_nodes(); ++n)
      for (int i : m.partition.interface) CHECK((cm.mesh.node(n) - m.mesh.node(i)).norm() > 1e-12);
    // Volume is conserved.
    auto volume = [](const softcut::mesh::TetMesh& mesh) {
      double v = 0;
      for (int t = 0; t < mesh.num_tets(); ++t) v += softcut::mesh::signed_volume(mesh, t);
      return v;
    };
    CHECK(volume(cm.mesh) == doctest::Approx(volume(m.mesh)).epsilon(1e-12));
    // The VTU export writes the cut mesh.
    const auto vtu = softcut::test::scratch_dir("cut_invariants_vtu") / "cut.vtu";
    sim::write_vtu(vtu, m, s);
    const std::string text = slurp(vtu);
    CHECK(text.find("NumberOfPoints=\"" + std::to_string(cm.mesh.num_nodes()) + "\" NumberOfCells=\"" +
                    std::to_string(cm.mesh.num_tets()) + "\"") != std::string::npos);
  }

  TEST_CASE("below the cutting pressure the blade only presses") {
    const sim::Model m = sim::compile(bar_cut_spec("cut_below", 1e9));
    sim::State s = sim::make_state(m);
    double max_pressure = 0, max_force = 0;
    while (s.frame < m.num_frames - 1) {
      sim::step(m, s);
      max_pressure = std::max(max_pressure, s.tools[0].pressure);
      max_force = std::max(max_force, s.tools[0].total_force.norm());
      CHECK_FALSE(s.tools[0].cutting);
    }
    CHECK_FALSE(s.cut);
    CHECK(s.cut_events.empty());
    CHECK(s.displacement.rows() == m.mesh.num_nodes());
    // It pressed: pressure = force / (length x 2 radius), and the force did work.
    CHECK(max_force > 0.1);
    CHECK(max_pressure == doctest::Approx(max_force / (0.04 * 0.003)).epsilon(1e-12));
  }

  TEST_CASE("the same scenario twice gives identical logs - new nodes are logged after the original ones") {
    std::string csv[2], events[2];
    int rest_nodes = 0, nodes_after = 0;
    for (int k = 0; k < 2; ++k) {
      const sim::Model m = sim::compile(bar_cut_spec("cut_repeat_" + std::to_string(k), 1000.0));
      sim::State s = sim::make_state(m);
      sim::Recorder rec(m);
      sim::run(m, s, rec, {});
      csv[k] = slurp(rec.dir() / "displacements.csv");
      for (const auto& e : s.cut_events)
        events[k] += std::to_string(e.frame) + " " + std::to_string(e.tets_split) + " " +
                     std::to_string(e.nodes_added) + " " + std::to_string(e.faces_separated) + ";";
      CHECK(softcut::test::read_json(rec.dir() / "summary.json")["cutting"]["scalpels"] == 1);
      rest_nodes = m.mesh.num_nodes();
      nodes_after = s.cut->mesh.num_nodes();
    }
    CHECK(!events[0].empty());
    CHECK(events[0] == events[1]);
    CHECK(csv[0] == csv[1]);
    // The last frame's rows end with every node made by cutting, in id order.
    const std::string last = "\n20,1.000000000e+00," + std::to_string(nodes_after - 1) + ",";
    CHECK(csv[0].find(last) != std::string::npos);
    CHECK(csv[0].find("\n20,1.000000000e+00," + std::to_string(rest_nodes) + ",") != std::string::npos);
  }

  TEST_CASE("a cut along the bar reaching the interface stops there with a warning - cut faces reach the scene") {
    sim::ScenarioSpec spec = bar_cut_spec("cut_interface", 1000.0);
    tools::ToolSpec& blade = spec.tools[0];
    blade.blade_axis = V(1, 0, 0);  // edge along the bar, 60 mm: beyond the 40 mm operational slab
    blade.blade_length = 0.06;
    for (auto& p : blade.path.points) p = V(0.05, 0.0105, p.z());
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    run_all(m, s);
    REQUIRE(s.cut);
    int warned = 0;
    for (const auto& e : s.cut_events) warned += !e.warnings.empty();
    CHECK(warned > 0);
    bool logged = false;
    for (const auto& w : s.warnings) logged |= w.find("scalpel 'blade'") != std::string::npos;
    CHECK(logged);
    CHECK(softcut::cut::count_components(s.cut->mesh) == 1);  // held together through the nonoperational ends
    // Flagged faces: boundary faces of operational tets that are not rest-surface faces.
    const softcut::render::SceneContent c = sim::scene_content(m, s);
    REQUIRE(c.cut_faces.size() == size_t(4 * s.cut->mesh.num_tets()));
    int flagged = 0;
    for (size_t k = 0; k < c.cut_faces.size(); ++k)
      if (c.cut_faces[k]) {
        ++flagged;
        CHECK(s.cut->operational_tet[k / 4] == 1);
        // Not a piece of the bar's outer surface (split outer faces stay outer).
        const int t = int(k / 4), f = int(k % 4);
        for (int axis = 1; axis < 3; ++axis)
          for (double plane : {0.0, 0.02}) {
            bool on = true;
            for (int j = 0; j < 3; ++j)
              on &= std::abs(s.cut->mesh.nodes(s.cut->mesh.tets(t, softcut::mesh::kTetFaces[f][j]), axis) - plane) < 1e-12;
            CHECK_FALSE(on);
          }
      }
    CHECK(flagged > 0);
    CHECK(c.operational.size() == size_t(s.cut->mesh.num_tets()));
  }

  TEST_CASE("a triangular blade slicing along its plane cuts the area it sweeps - the edge alone does not") {
    double extent[2] = {0, 0};
    for (int tri = 0; tri < 2; ++tri) {
      sim::ScenarioSpec spec = bar_cut_spec("cut_triangle_" + std::to_string(tri), 1000.0);
      tools::ToolSpec& blade = spec.tools[0];
      spec.mesh.options["nx"] = 20;    // 5 mm cells along the bar
      blade.blade_axis = V(1, 0, 0);  // 10 mm edge along the bar
      blade.blade_length = 0.01;
      if (tri) blade.blade_back = V(0, 0, 0.02);
      // Press at the top, stab 15 mm down, then slice 12 mm along x (along the edge).
      blade.path.times = {0.0, 0.3, 0.5, 1.0};
      blade.path.points = {V(0.045, 0.0105, 0.0205), V(0.045, 0.0105, 0.0205), V(0.045, 0.0105, 0.0055),
                           V(0.057, 0.0105, 0.0055)};
      const sim::Model m = sim::compile(spec);
      sim::State s = sim::make_state(m);
      run_all(m, s);
      REQUIRE(s.cut);
      double lo = 1, hi = -1;
      for (int n = m.mesh.num_nodes(); n < s.cut->mesh.num_nodes(); ++n)
        lo = std::min(lo, s.cut->mesh.nodes(n, 0)), hi = std::max(hi, s.cut->mesh.nodes(n, 0));
      extent[tri] = hi - lo;
      CHECK(softcut::cut::count_components(s.cut->mesh) == 1);
    }
    // Nodes separate behind the cut front only: the edge's stab opens the
    // x = 45 mm column (its ends stay joined, at the front); the edge sliding
    // along itself sweeps nothing. The triangle's slice opens the next column.
    CHECK(extent[0] < 1e-9);
    CHECK(extent[1] > 0.005 - 1e-9);
  }
}
