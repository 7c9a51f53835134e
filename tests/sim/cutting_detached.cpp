// Pieces cut free (engine/sim/cutting.cpp update_detached, drop_loads_on_held,
// hold_detached; docs/cutting.md "Pieces cut free").
#include <doctest/doctest.h>

#include <algorithm>

#include <array>

#include <set>

#include <Eigen/SparseCholesky>

#include "fem/assembly.hpp"
#include "sim/cutting.hpp"
#include "sim/model.hpp"
#include "sim/step.hpp"
#include "fixtures.hpp"
#include "test_support.hpp"

using V = Eigen::Vector3d;
namespace sim = softcut::sim;
namespace tools = softcut::tools;

namespace {

// A 0.1 x 0.02 x 0.02 m bar (10 x 4 x 4 cells), operational for x in
// [op_lo, op_hi], fixed at x = 0 (and at x = 0.1 when `both_ends`), a small
// load on its top. A scalpel presses the top at x = cut_x and goes down
// through the whole section: with one end fixed, the far side is cut free.
// A probe pokes the free end after the cut.
sim::ScenarioSpec free_cut_spec(const std::string& name, const std::string& backend, double op_lo, double op_hi,
                                double cut_x, bool both_ends = false) {
  sim::ScenarioSpec s = softcut::test::held_bar_spec(name, V(0.1, 0.02, 0.02), 5e5, op_lo, op_hi, both_ends);
  sim::LoadSpec top;
  top.name = "top";
  top.nodes = sim::NodeSelector::box(V(0.015, -1, 0.02), V(0.095, 1, 1));
  top.direction = V(0, 0, -1);
  top.magnitude = tools::Ramp::linear_ramp(0.0, 0.002, 0.0, 1.2);
  s.loads.push_back(top);
  tools::ToolSpec blade;
  blade.name = "blade";
  blade.kind = tools::ToolSpec::Kind::scalpel;
  blade.blade_length = 0.04;
  blade.blade_axis = V(0, 1, 0);
  blade.radius = 0.0015;
  blade.cut_pressure = 100.0;
  blade.direction = V(0, 0, -1);
  blade.force = tools::Ramp::linear_ramp(0.0, 0.02, 0.0, 0.2);  // 0.012 N = 100 Pa over 40 mm x 3 mm
  blade.path.kind = tools::Path::Kind::polyline;
  blade.path.times = {0.0, 0.3, 1.0};
  blade.path.points = {V(cut_x, 0.01, 0.0205), V(cut_x, 0.01, 0.0205), V(cut_x, 0.01, -0.004)};
  s.tools.push_back(blade);
  tools::ToolSpec probe;
  probe.name = "probe";
  probe.path = tools::Path::fixed_at(V(0.1, 0.01, 0.02));
  probe.radius = 0.0045;
  probe.force = tools::Ramp::constant_value(0.001);
  probe.start = 1.05;
  s.tools.push_back(probe);
  s.timeline.duration = 1.3;
  s.timeline.fps = 20.0;
  s.outputs.dir = softcut::test::scratch_dir(name);
  s.solver.backend = softcut::backend::parse_backend(backend);
  s.solver.cg_tolerance = 1e-12;
  return s;
}

// Independent reference: K u = f over every tet of the cut mesh with the
// clamped nodes at zero and the held nodes at their held displacement
// (K_ff u_f = f_f - K_fc u_c), by a sparse LDLT of its own.
Eigen::MatrixX3d held_reference(const sim::CutMesh& cm, const Eigen::MatrixX3d& forces) {
  const int nn = cm.mesh.num_nodes();
  const softcut::fem::SparseMatrix K = softcut::fem::assemble_stiffness(cm.mesh, cm.tet_material);
  std::vector<char> used(size_t(nn), 0);
  for (int t = 0; t < cm.mesh.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) used[size_t(cm.mesh.tets(t, k))] = 1;
  Eigen::VectorXd uc = Eigen::VectorXd::Zero(3 * nn);
  std::vector<int> index(size_t(3 * nn), -1);
  int nf = 0;
  for (int v = 0; v < nn; ++v)
    for (int a = 0; a < 3; ++a) {
      if (cm.node_held[size_t(v)]) uc(3 * v + a) = cm.held_displacement(v, a);
      if (used[size_t(v)] && !cm.node_clamped[size_t(v)] && !cm.node_held[size_t(v)]) index[size_t(3 * v + a)] = nf++;
    }
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(nf);
  for (int v = 0; v < nn; ++v)
    for (int a = 0; a < 3; ++a)
      if (index[size_t(3 * v + a)] >= 0) b(index[size_t(3 * v + a)]) = forces(v, a);
  for (int col = 0; col < K.outerSize(); ++col)
    for (softcut::fem::SparseMatrix::InnerIterator it(K, col); it; ++it) {
      const int r = index[size_t(it.row())], c = index[size_t(col)];
      if (r < 0) continue;
      if (c >= 0) trip.emplace_back(r, c, it.value());
      else b(r) -= it.value() * uc(col);
    }
  Eigen::SparseMatrix<double> Kff(nf, nf);
  Kff.setFromTriplets(trip.begin(), trip.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Kff);
  REQUIRE(ldlt.info() == Eigen::Success);
  const Eigen::VectorXd x = ldlt.solve(b);
  Eigen::MatrixX3d u(nn, 3);
  for (int v = 0; v < nn; ++v)
    for (int a = 0; a < 3; ++a) {
      const int i = index[size_t(3 * v + a)];
      u(v, a) = i >= 0 ? x(i) : uc(3 * v + a);
    }
  return u;
}

int count_containing(const std::vector<std::string>& lines, const std::string& what) {
  int n = 0;
  for (const auto& l : lines) n += l.find(what) != std::string::npos;
  return n;
}

// Runs the scenario to the end, checking every frame from the one that cut
// the piece free: the attached part against held_reference, the piece held
// exactly at its displacement at separation. Returns the frames checked after it.
int run_and_check_free_piece(const sim::Model& m, sim::State& s) {
  int separation = -1, after = 0;
  Eigen::MatrixX3d at_separation;
  while (s.frame < m.num_frames - 1) {
    const Eigen::MatrixX3d before = s.displacement;
    sim::step(m, s);
    if (!s.cut || s.cut->detached_pieces == 0) continue;
    const sim::CutMesh& cm = *s.cut;
    if (separation < 0) {
      separation = s.frame;
      REQUIRE(!s.cut_events.empty());
      const sim::CutEvent& ev = s.cut_events.back();
      CHECK(ev.frame == s.frame);
      CHECK(ev.pieces_freed == 1);
      CHECK(ev.tets_freed > 0);
      REQUIRE(ev.warnings.size() >= 1);
      CHECK(count_containing(ev.warnings, "cut free at frame " + std::to_string(s.frame)) == 1);
      CHECK(count_containing(ev.warnings, "held at its displacement at separation") == 1);
      // One stroke cut it, and the warning says which (issue #40 item 9).
      CHECK(count_containing(ev.warnings, "by the cut of the stroke begun at t = ") == 1);
      CHECK(count_containing(ev.warnings, "merge into one cut") == 0);
      // Held where the last solve left it (pre-existing nodes keep their rows).
      int held_old = 0;
      for (int v = 0; v < int(before.rows()); ++v)
        if (cm.node_held[size_t(v)]) {
          ++held_old;
          CHECK(cm.held_displacement.row(v) == before.row(v));
        }
      CHECK(held_old > 0);
      at_separation = s.displacement;
    } else {
      ++after;
    }
    // The piece stays exactly where it was.
    int held = 0;
    for (int v = 0; v < int(at_separation.rows()); ++v)
      if (cm.node_held[size_t(v)]) {
        ++held;
        CHECK(s.displacement.row(v) == at_separation.row(v));
      }
    CHECK(held > 0);
    // The rest equals a whole-mesh solve with the piece constrained.
    const Eigen::MatrixX3d ref = held_reference(cm, s.forces);
    double scale = 0, err = 0;
    for (int v = 0; v < cm.mesh.num_nodes(); ++v) {
      if (cm.node_held[size_t(v)] || sim::node_set(m, s, v) == softcut::hybrid::NodeSet::interior) continue;
      scale = std::max(scale, ref.row(v).cwiseAbs().maxCoeff());
      err = std::max(err, (s.displacement.row(v) - ref.row(v)).cwiseAbs().maxCoeff());
    }
    REQUIRE(scale > 0);
    CHECK(err <= 1e-8 * scale);
  }
  CHECK(separation > 0);
  return after;
}

}  // namespace

TEST_SUITE("sim/cutting (pieces cut free)") {
  TEST_CASE("a through-cut near the free end frees an operational piece - held and the rest exact on every backend") {
    for (const std::string backend : {"cpu", "direct", "monolithic"}) {
      CAPTURE(backend);
      const sim::Model m = sim::compile(free_cut_spec("cut_free_" + backend, backend, 0.03, 0.1, 0.0812));
      sim::State s = sim::make_state(m);
      CHECK(run_and_check_free_piece(m, s) >= 5);
      REQUIRE(s.cut);
      CHECK(softcut::cut::count_components(s.cut->mesh) == 2);
      const sim::DetachedCounts d = sim::detached_counts(s);
      CHECK(d.pieces == 1);
      // About two of ten cells: 2 x 16 cells x 6 tets plus the split ones.
      CHECK(d.tets >= 2 * 16 * 6);
      CHECK(d.tets < 3 * 16 * 6);
      // The load and the probe on the piece are ignored, each warned about once.
      CHECK(count_containing(s.warnings, "load 'top' acts on a piece cut free") == 1);
      CHECK(count_containing(s.warnings, "tool 'probe' acts on a piece cut free") == 1);
      CHECK(count_containing(s.warnings, "cut free at frame") == 1);
      REQUIRE(!s.tools[1].nodes.empty());
      for (int n : s.tools[1].nodes) {
        CHECK(sim::is_held_node(s, n));
        CHECK(s.forces.row(n).norm() == 0.0);
      }
    }
  }

  TEST_CASE("a piece freed with nonoperational tets and interface nodes is held too - hybrid equals monolithic") {
    const sim::Model mono = sim::compile(free_cut_spec("cut_free_nonop_mono", "monolithic", 0.03, 0.07, 0.0512));
    sim::State t = sim::make_state(mono);
    CHECK(run_and_check_free_piece(mono, t) >= 5);
    REQUIRE(t.cut);
    for (const std::string backend : {"cpu", "direct"}) {
      CAPTURE(backend);
      const sim::Model m = sim::compile(free_cut_spec("cut_free_nonop_" + backend, backend, 0.03, 0.07, 0.0512));
      REQUIRE(m.partition.interface.size() > 0);
      sim::State s = sim::make_state(m);
      CHECK(run_and_check_free_piece(m, s) >= 5);
      REQUIRE(s.cut);
      REQUIRE((s.cut->mesh.tets.array() == t.cut->mesh.tets.array()).all());
      // The freed piece holds interface nodes (x = 0.07) and nonoperational ones.
      int interface_held = 0, nonop_held = 0;
      for (int v = 0; v < m.mesh.num_nodes(); ++v) {
        if (!s.cut->node_held[size_t(v)]) continue;
        interface_held += m.partition.node_set[size_t(v)] == softcut::hybrid::NodeSet::interface;
        nonop_held += m.partition.node_set[size_t(v)] == softcut::hybrid::NodeSet::surface;
      }
      CHECK(interface_held > 0);
      CHECK(nonop_held > 0);
      double scale = 0, err = 0;
      for (int v = 0; v < s.cut->mesh.num_nodes(); ++v) {
        if (sim::node_set(m, s, v) == softcut::hybrid::NodeSet::interior) continue;
        scale = std::max(scale, t.displacement.row(v).cwiseAbs().maxCoeff());
        err = std::max(err, (s.displacement.row(v) - t.displacement.row(v)).cwiseAbs().maxCoeff());
      }
      CHECK(err <= 1e-8 * scale);
    }
  }

  TEST_CASE("an implicit grasper holding the end that is cut free is ignored from then on - one warning") {
    auto spec = free_cut_spec("cut_free_grasp", "cpu", 0.03, 0.1, 0.0812);
    spec.tools.pop_back();  // no probe
    const V p(0.1, 0.01, 0.02);
    spec.tools.push_back(softcut::test::spring_grasper(20.0, 0.0045, tools::Path::polyline({0.0, 0.5}, {p, p + V(0, 0, 2e-4)})));
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    CHECK(run_and_check_free_piece(m, s) >= 5);
    REQUIRE(!s.tools[1].nodes.empty());
    for (int n : s.tools[1].nodes) CHECK(sim::is_held_node(s, n));
    CHECK(count_containing(s.warnings, "tool 'jaw' acts on a piece cut free") == 1);
    // It lifted the end before the cut: the piece is held lifted, not dropped to zero.
    double z = 0;
    for (int n : s.tools[1].nodes) z += s.displacement(n, 2);
    CHECK(z > 0);
  }

  // A blade through the middle of a grasper's grip: every grip point is
  // bound anew to a face of the cut surface (one side each, no point tying
  // the lips together), and the hybrid answer still equals the whole-mesh one.
  TEST_CASE("a cut through a grip binds each grip point to one side - hybrid equals monolithic after it") {
    sim::State runs[2];
    std::vector<char> interior;
    const char* backends[2] = {"direct", "monolithic"};
    for (int b = 0; b < 2; ++b) {
      auto spec = free_cut_spec(std::string("cut_grip_") + backends[b], backends[b], 0.03, 0.07, 0.0512, true);
      spec.tools.pop_back();  // no probe
      const V p(0.0512, 0.01, 0.02);
      spec.tools.push_back(softcut::test::spring_grasper(20.0, 0.004, tools::Path::polyline({0.0, 1.3}, {p, p + V(0, 0, 2e-4)})));
      const sim::Model m = sim::compile(spec);
      sim::State& s = runs[b];
      s = sim::make_state(m);
      while (s.frame < m.num_frames - 1) sim::step(m, s);
      REQUIRE(s.cut);
      CHECK(softcut::cut::count_components(s.cut->mesh) == 2);
      const tools::ToolState& ts = s.tools[1];
      REQUIRE(ts.engaged);
      std::set<std::array<int, 3>> faces;
      for (int f = 0; f < s.cut->surface.faces.rows(); ++f) {
        std::array<int, 3> k{s.cut->surface.faces(f, 0), s.cut->surface.faces(f, 1), s.cut->surface.faces(f, 2)};
        std::sort(k.begin(), k.end());
        faces.insert(k);
      }
      int left = 0, right = 0;
      const Eigen::MatrixX3d x = sim::deformed_positions(m, s);
      for (const auto& gp : ts.grip) {
        std::array<int, 3> k = gp.nodes;
        std::sort(k.begin(), k.end());
        CHECK(faces.count(k) == 1);
        const double px = gp.at(x).x();
        left += px < 0.049, right += px > 0.051;
      }
      CHECK(left > 0);
      CHECK(right > 0);
      CHECK(std::abs(ts.total_force.z()) > 0);
      if (b == 0)  // the hybrid run leaves interior nonoperational rows unsolved
        for (int v = 0; v < s.cut->mesh.num_nodes(); ++v) interior.push_back(sim::node_set(m, s, v) == softcut::hybrid::NodeSet::interior);
    }
    const Eigen::MatrixX3d& a = runs[0].displacement;
    const Eigen::MatrixX3d& r = runs[1].displacement;
    REQUIRE(a.rows() == r.rows());
    double err = 0;
    for (Eigen::Index v = 0; v < a.rows(); ++v)
      if (!interior[size_t(v)]) err = std::max(err, (a.row(v) - r.row(v)).cwiseAbs().maxCoeff());
    CHECK(r.cwiseAbs().maxCoeff() > 1e-6);
    CHECK(err <= 1e-8 * r.cwiseAbs().maxCoeff());
  }

  TEST_CASE("a through-cut of a bar fixed at both ends frees nothing") {
    const sim::Model m = sim::compile(free_cut_spec("cut_free_none", "cpu", 0.03, 0.07, 0.0512, true));
    sim::State s = sim::make_state(m);
    while (s.frame < m.num_frames - 1) sim::step(m, s);
    REQUIRE(s.cut);
    CHECK(softcut::cut::count_components(s.cut->mesh) == 2);
    const sim::DetachedCounts d = sim::detached_counts(s);
    CHECK(d.pieces == 0);
    CHECK(d.tets == 0);
    for (char h : s.cut->node_held) CHECK(h == 0);
    CHECK(s.cut->node_fixed == s.cut->node_clamped);
    for (const auto& e : s.cut_events) CHECK(e.pieces_freed == 0);
    CHECK(count_containing(s.warnings, "cut free") == 0);
  }
}
