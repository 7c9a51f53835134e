#include "sim/step.hpp"

#include <doctest/doctest.h>

#include <Eigen/LU>
#include <algorithm>

#include "fixtures.hpp"
#include "test_support.hpp"

using V = Eigen::Vector3d;
namespace sim = softcut::sim;
namespace tools = softcut::tools;

TEST_SUITE("sim/step") {
  TEST_CASE("an explicit spring grasper on a stationary target converges to the closed-form force") {
    // Grasp at the free-end corner with a jaw far smaller than the faces (it
    // holds the triangles there, the corner node weighing most), then hold the
    // tip 1 mm above. Equilibrium of the explicit iteration: with W the grip's
    // weights and C its nodes' compliance, the point forces solve
    // (I/kp + W C W^T) f = T - X_p, and the nodes take W^T f.
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_step_spring"), 6.0);
    spec.loads.clear();
    const sim::Model probe_model = sim::compile(spec);
    const int corner = 5;  // (0.1, 0, 0)
    REQUIRE((probe_model.mesh.node(corner) - V(0.1, 0, 0)).norm() < 1e-15);
    auto compliance = [&](const std::vector<int>& nodes) {
      const Eigen::Index m = Eigen::Index(3 * nodes.size());
      Eigen::MatrixXd C(m, m);
      for (Eigen::Index c = 0; c < m; ++c) {
        Eigen::MatrixX3d f = Eigen::MatrixX3d::Zero(probe_model.mesh.num_nodes(), 3), u;
        f(nodes[size_t(c / 3)], c % 3) = 1.0;
        softcut::backend::SolverRun warm;
        softcut::backend::SolveStats st;
        probe_model.solver->solve(f, u, warm, st);
        for (size_t j = 0; j < nodes.size(); ++j) C.block<3, 1>(Eigen::Index(3 * j), c) = u.row(nodes[j]).transpose();
      }
      return C;
    };
    const double k = 0.3 / compliance({corner}).norm();  // k ||C|| < 1: the frame-to-frame iteration contracts
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
    const tools::ToolState& ts = s.tools[0];
    REQUIRE(std::count(ts.nodes.begin(), ts.nodes.end(), corner) == 1);
    const Eigen::MatrixXd W = softcut::test::grip_weights(ts);
    const Eigen::MatrixXd C = compliance(ts.nodes);
    const Eigen::MatrixXd A = W * C * W.transpose();
    const Eigen::VectorXd gap = softcut::test::grip_gaps(ts, m.mesh.nodes, Eigen::MatrixX3d::Zero(m.mesh.num_nodes(), 3));
    const Eigen::VectorXd h =
        W.transpose() * (Eigen::MatrixXd::Identity(A.rows(), A.cols()) * double(ts.grip.size()) / k + A).lu().solve(gap);
    V expected = V::Zero();
    for (size_t j = 0; j < ts.nodes.size(); ++j) expected += h.segment<3>(Eigen::Index(3 * j));
    CHECK(expected.z() > 0.5 * k * d.z());  // lifted, against the tissue's pull
    CHECK((s.tools[0].total_force - expected).norm() <= 1e-9 * expected.norm());
    const Eigen::VectorXd u = C * h;
    for (size_t j = 0; j < ts.nodes.size(); ++j)
      CHECK((s.displacement.row(ts.nodes[j]).transpose() - u.segment<3>(Eigen::Index(3 * j))).norm() <= 1e-9 * u.norm());
    CHECK(s.tools[0].engaged);
  }

  TEST_CASE("a force-driven probe pressing the top face moves it down by the load's response") {
    auto spec = softcut::test::cantilever_spec(softcut::test::scratch_dir("sim_step_probe"), 0.1);
    spec.loads.clear();
    tools::ToolSpec p;
    p.name = "probe";
    p.path = tools::Path::fixed_at(V(0.1, 0.01, 0.02));
    p.radius = 0.0101;  // a contact circle of 10 mm around the free end's top-edge centre
    p.force = tools::Ramp::constant_value(0.003);
    spec.tools.push_back(p);
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::step(m, s);
    REQUIRE(s.tools[0].grip.size() >= 7);
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
