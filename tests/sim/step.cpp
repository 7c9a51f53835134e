#include "sim/step.hpp"

#include <doctest/doctest.h>

#include <Eigen/LU>

#include "fixtures.hpp"
#include "test_support.hpp"

using V = Eigen::Vector3d;
namespace sim = softcut::sim;
namespace tools = softcut::tools;

TEST_SUITE("sim/step") {
  TEST_CASE("an explicit spring grasper on a stationary target converges to the closed-form force") {
    // Grasp the free-end corner node, then hold the tip 1 mm above its rest
    // position. Equilibrium: f = k (d - C f) with C the node's 3x3 compliance,
    // i.e. f = (I + k C)^-1 k d.
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_step_spring"), 6.0);
    spec.loads.clear();
    const sim::Model probe_model = sim::compile(spec);
    const int corner = 5;  // (0.1, 0, 0)
    REQUIRE((probe_model.mesh.node(corner) - V(0.1, 0, 0)).norm() < 1e-15);
    Eigen::Matrix3d C;
    for (int a = 0; a < 3; ++a) {
      Eigen::MatrixX3d f = Eigen::MatrixX3d::Zero(probe_model.mesh.num_nodes(), 3), u;
      f(corner, a) = 1.0;
      sim::SolverRun warm;
      sim::SolveStats st;
      probe_model.solver->solve(f, u, warm, st);
      C.col(a) = u.row(corner).transpose();
    }
    const double k = 0.3 / C.norm();  // k ||C|| < 1: the frame-to-frame iteration contracts
    const V d(0, 0, 1e-3);

    tools::ToolSpec g;
    g.name = "grasper";
    g.kind = tools::ToolSpec::Kind::grasper;
    g.drive = tools::ToolSpec::Drive::spring;
    g.stiffness = k;
    g.implicit = false;  // the frame-to-frame fixed point (springs.cpp tests the implicit one)
    g.radius = 1e-4;
    g.path = tools::Path::polyline({0.0, 0.1}, {V(0.1, 0, 0), V(0.1, 0, 0) + d});
    spec.tools.push_back(g);
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    for (int i = 0; i < m.num_frames; ++i) sim::step(m, s);
    REQUIRE(s.tools[0].nodes == std::vector<int>{corner});
    const V expected = (Eigen::Matrix3d::Identity() + k * C).inverse() * (k * d);
    CHECK((s.tools[0].total_force - expected).norm() <= 1e-9 * expected.norm());
    CHECK((s.displacement.row(corner).transpose() - C * expected).norm() <= 1e-9 * (C * expected).norm());
    CHECK(s.tools[0].engaged);
  }

  TEST_CASE("a force-driven probe pressing the top face moves it down by the load's response") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_step_probe"), 0.1);
    spec.loads.clear();
    tools::ToolSpec p;
    p.name = "probe";
    p.path = tools::Path::fixed_at(V(0.1, 0.01, 0.02));
    p.radius = 0.0101;  // 4 nodes of the free end: top-edge centre, its 2 edge neighbours, 1 below
    p.force = tools::Ramp::constant_value(0.003);
    spec.tools.push_back(p);
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::step(m, s);
    REQUIRE(s.tools[0].nodes.size() == 4);
    CHECK(s.tools[0].total_force.norm() == doctest::Approx(0.003));
    CHECK(s.tools[0].total_force.z() < 0);
    CHECK(s.forces.colwise().sum().norm() == doctest::Approx(0.003));
    CHECK(s.displacement.col(2).minCoeff() < 0);
  }

  TEST_CASE("script knobs: disabled loads, scale, stop request") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_step_knobs"), 1.0);
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    for (int i = 0; i <= 5; ++i) sim::step(m, s);  // t = 0.5
    const double full = s.forces.col(2).sum();
    CHECK(full == doctest::Approx(-0.005));
    s.loads[0].scale = 2.0;
    sim::step(m, s);  // t = 0.6
    CHECK(s.forces.col(2).sum() == doctest::Approx(-0.012));
    const double loaded = s.displacement.norm();
    s.loads[0].enabled = false;
    sim::step(m, s);
    CHECK(s.forces.norm() == 0);
    CHECK(s.displacement.norm() <= 1e-12 * loaded);  // running sums of the hybrid update round off
  }
}
