// The frame's nonlinear stage (hybrid/nonlinear_solve through sim::step):
// the hybrid's answer for a corotational or neo-Hookean operational region
// equals the monolithic backend's solve of the same mixed model on the
// whole mesh (DESIGN.md §1b), under loads, a prescribed lift and a cut; and
// the nonlinear law is really in force (the answer leaves the linear one).
#include "sim/step.hpp"

#include <doctest/doctest.h>

#include <string>

#include "sim/cutting.hpp"
#include "sim/model.hpp"
#include "fixtures.hpp"
#include "test_support.hpp"

using V = Eigen::Vector3d;
namespace sim = softcut::sim;
namespace tools = softcut::tools;
using softcut::backend::Backend;
using softcut::fem::MaterialModel;

namespace {

// The largest difference over the nodes both solvers report (the hybrid
// leaves condensed interior nodes unsolved), and the largest displacement.
struct Gap {
  double diff = 0, scale = 0;
};
Gap compare(const sim::Model& m, const sim::State& s, const sim::State& t) {
  REQUIRE(s.displacement.rows() == t.displacement.rows());
  Gap g;
  for (int n = 0; n < s.displacement.rows(); ++n) {
    if (sim::node_set(m, s, n) == softcut::hybrid::NodeSet::interior) continue;
    g.diff = std::max(g.diff, (s.displacement.row(n) - t.displacement.row(n)).cwiseAbs().maxCoeff());
    g.scale = std::max(g.scale, t.displacement.row(n).cwiseAbs().maxCoeff());
  }
  return g;
}

// Steps the hybrid (direct: its kept factor preconditions Newton) and the monolithic model of `spec` side by side and
// checks every frame; returns the hybrid's last state.
sim::State hybrid_equals_monolithic(sim::ScenarioSpec spec, int* newton_frames = nullptr,
                                    Backend hybrid_backend = Backend::direct) {
  spec.solver.backend = hybrid_backend;
  const sim::Model hybrid = sim::compile(spec);
  spec.solver.backend = Backend::monolithic;
  spec.outputs.dir = spec.outputs.dir.string() + "_mono";
  const sim::Model mono = sim::compile(spec);
  sim::State s = sim::make_state(hybrid), t = sim::make_state(mono);
  int loaded = 0;
  while (s.frame < hybrid.num_frames - 1) {
    sim::step(hybrid, s);
    sim::step(mono, t);
    const Gap g = compare(hybrid, s, t);
    CAPTURE(s.frame);
    CHECK(g.diff <= 1e-8 * g.scale);  // frame 0 is unloaded: both exactly zero
    loaded += g.scale > 0;
  }
  CHECK(loaded == hybrid.num_frames - 1);
  CHECK(s.stats.newton_frames == t.stats.newton_frames);
  if (newton_frames) *newton_frames = s.stats.newton_frames;
  return s;
}

}  // namespace

TEST_SUITE("sim/step_nonlinear") {
  TEST_CASE("a corotational or neo-Hookean slab under a tip load: hybrid == monolithic every frame, apart from linear") {
    for (const MaterialModel law : {MaterialModel::corotational, MaterialModel::neohookean}) {
      CAPTURE(int(law));
      // 0.03 N at the tip of the 5 kPa bar: its slab turns by about 0.3 rad.
      sim::ScenarioSpec spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("nonlinear_tip"), 1.0, 0.03);
      spec.timeline.fps = 5;
      sim::ScenarioSpec linear = spec;
      spec.materials[0].model = law;
      int newton = 0;
      const sim::State s = hybrid_equals_monolithic(spec, &newton);
      CHECK(newton == 6);  // every frame but the unloaded first one is solved by Newton
      // The same frames with the linear law differ by more than 1 %: the law is in force.
      const sim::Model lm = sim::compile(linear);
      sim::State l = sim::make_state(lm);
      while (l.frame < lm.num_frames - 1) sim::step(lm, l);
      CHECK(l.stats.newton_frames == 0);
      const Gap g = compare(lm, l, s);
      CHECK(g.diff > 0.01 * g.scale);
    }
  }

  TEST_CASE("the CG backend's Newton (block Jacobi, no factor) == monolithic every frame") {
    // (the gpu backend takes the same path: tests/app checks through_cut and
    // tensioned_incision, corotational, on it against their reference logs)
    sim::ScenarioSpec spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("nonlinear_cg"), 1.0, 0.03);
    spec.timeline.fps = 5;
    spec.materials[0].model = MaterialModel::corotational;
    int newton = 0;
    hybrid_equals_monolithic(spec, &newton, Backend::cpu);
    CHECK(newton == 6);
  }

  TEST_CASE("a prescribed lift of the tip: hybrid == monolithic, the lifted nodes exactly where they were sent") {
    sim::ScenarioSpec spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("nonlinear_lift"), 1.0, 0.0);
    spec.timeline.fps = 5;
    spec.loads.clear();
    spec.materials[0].model = MaterialModel::corotational;
    spec.operational.min = V(0.05, -1, -1);  // the moved nodes touch operational tets only
    spec.operational.max = V(1, 1, 1);
    const auto tip = sim::NodeSelector::box(V(0.1, -1, -1), V(1, 1, 1));
    spec.fixed = sim::NodeSelector::combine(sim::NodeSelector::Kind::union_of, {spec.fixed, tip});
    sim::MotionSpec lift;
    lift.name = "lift";
    lift.nodes = tip;
    lift.path = tools::Path::polyline({0.0, 1.0}, {V(0, 0, 0), V(0, 0, 0.02)});  // 20 mm up
    spec.motions.push_back(lift);
    const sim::State s = hybrid_equals_monolithic(spec);
    const sim::Model m = sim::compile(spec);
    int lifted = 0;
    for (int n = 0; n < m.mesh.num_nodes(); ++n)
      if (m.mesh.node(n).x() >= 0.1 - 1e-12) {
        CHECK(s.displacement(n, 2) == doctest::Approx(0.02).epsilon(1e-12));
        ++lifted;
      }
    CHECK(lifted == 9);
  }

  TEST_CASE("a cut through a corotational slab: hybrid == monolithic before and after it") {
    // held at both ends, pressed on top, a blade down through the middle
    // (the bar of sim/cutting's through-cut), with the corotational law.
    sim::ScenarioSpec spec = softcut::test::held_bar_spec("nonlinear_cut", V(0.1, 0.02, 0.02), 5e3, 0.03, 0.07, true);
    spec.materials[0].model = MaterialModel::corotational;
    sim::LoadSpec top;
    top.name = "top";
    top.nodes = sim::NodeSelector::box(V(0.015, -1, 0.02), V(0.085, 1, 1));
    top.direction = V(0, 0, -1);
    top.magnitude = tools::Ramp::linear_ramp(0.0, 0.05, 0.0, 0.2);
    spec.loads.push_back(top);
    spec.tools.push_back(softcut::test::through_cut_blade(1000));
    spec.timeline.duration = 1.0;
    spec.timeline.fps = 10.0;
    spec.outputs.dir = softcut::test::scratch_dir("nonlinear_cut");
    spec.solver.cg_tolerance = 1e-12;
    const sim::State s = hybrid_equals_monolithic(spec);
    REQUIRE(s.cut);
    CHECK(s.cut_events.size() >= 2);
    CHECK(s.stats.newton_frames >= 8);
  }
}
