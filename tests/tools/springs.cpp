// Implicit grasper springs (tools/springs.hpp) on a made-up linear system:
// five nodes whose unit-load responses are the columns of a random SPD
// compliance, so the closed form can be written down without any FEM.
#include "tools/springs.hpp"

#include <doctest/doctest.h>

#include <Eigen/Cholesky>

#include "core/error.hpp"
#include "test_support.hpp"

namespace tools = softcut::tools;
using V = Eigen::Vector3d;
using softcut::test::contains;

namespace {

// One implicit grasper holding two points, on triangles (0, 1, 2) and
// (2, 3, 4); node 4 fixed; compliance C (15 x 15, m/N) SPD on nodes 0..3,
// zero on the fixed node's rows and columns.
struct Setup {
  softcut::mesh::TetMesh mesh;
  Eigen::MatrixXd C;
  std::vector<tools::ToolSpec> specs{1};
  std::vector<tools::ToolState> states{1};
  Eigen::MatrixX3d u0, f0;
  int response_calls = 0;
  long generation = 3;
  std::function<V(int)> held;

  Setup() {
    mesh.nodes.resize(5, 3);
    for (int i = 0; i < 5; ++i) mesh.nodes.row(i) << 0.01 * i, 0.002 * i * i, -0.001 * i;
    std::srand(7);
    const Eigen::MatrixXd B = Eigen::MatrixXd::Random(15, 15);
    C = 1e-3 * (B * B.transpose() / 15.0 + Eigen::MatrixXd::Identity(15, 15));
    C.bottomRows(3).setZero(), C.rightCols(3).setZero();  // node 4 is fixed: it does not move
    tools::ToolSpec& g = specs[0];
    g.kind = tools::ToolSpec::Kind::grasper;
    g.drive = tools::ToolSpec::Drive::spring;
    g.implicit = true;
    g.stiffness = 300.0;  // N/m over its two points: k ||C|| well above 1
    tools::ToolState& s = states[0];
    s.tip = V(0.02, 0.01, 0.005);
    s.nodes = {0, 1, 2, 3, 4};
    s.grip.resize(2);
    s.grip[0].nodes = {0, 1, 2}, s.grip[0].weights = V(0.5, 0.3, 0.2);
    s.grip[1].nodes = {2, 3, 4}, s.grip[1].weights = V(0.1, 0.6, 0.3);
    s.offsets = {V(-0.001, 0.0, 0.002), V(0.003, -0.001, 0.0)};
    u0 = 1e-3 * Eigen::MatrixX3d::Random(5, 3);
    u0.row(4).setZero();  // fixed
    f0 = Eigen::MatrixX3d::Random(5, 3);
  }

  tools::SpringSystem system() {
    tools::SpringSystem sys;
    sys.mesh = &mesh;
    sys.fixed = [](int n) { return n == 4; };
    sys.held = held;
    sys.generation = generation;
    sys.unit_responses = [this](const std::vector<int>& nodes, Eigen::MatrixXd& out) {
      ++response_calls;
      out.resize(15, Eigen::Index(3 * nodes.size()));
      for (size_t j = 0; j < nodes.size(); ++j) out.middleCols(3 * Eigen::Index(j), 3) = C.middleCols(3 * nodes[j], 3);
    };
    return sys;
  }

  // The closed form: free grasped nodes 0..3; W (6 x 12) the points'
  // weights on them; (I / kp + W C_gg W^T) f = T + o - X_w - h_w - W u0_g.
  struct Expected {
    Eigen::VectorXd f;     // (6) N per point
    Eigen::MatrixX3d u;    // (5 x 3) m
  };
  Expected expected(const V& held3 = V::Zero()) const {
    Eigen::MatrixXd W = Eigen::MatrixXd::Zero(6, 12);
    const tools::ToolState& s = states[0];
    Eigen::VectorXd d(6);
    for (int p = 0; p < 2; ++p) {
      V at_rest = V::Zero();
      for (int j = 0; j < 3; ++j) {
        const int n = s.grip[size_t(p)].nodes[size_t(j)];
        const double w = s.grip[size_t(p)].weights(j);
        at_rest += w * mesh.node(n);
        if (n == 3) at_rest += w * held3;
        if (n != 4) W.block(3 * p, 3 * n, 3, 3).diagonal().array() += w;
      }
      d.segment<3>(3 * p) = s.tip + s.offsets[size_t(p)] - at_rest;
    }
    const Eigen::MatrixXd Cgg = C.topLeftCorner(12, 12);
    Eigen::VectorXd u0g(12);
    for (int n = 0; n < 4; ++n) u0g.segment<3>(3 * n) = u0.row(n).transpose();
    const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(6, 6) / (specs[0].stiffness / 2) + W * Cgg * W.transpose();
    Expected e;
    e.f = A.llt().solve(d - W * u0g);
    const Eigen::VectorXd du = C.leftCols(12) * (W.transpose() * e.f);
    e.u = u0;
    for (int n = 0; n < 5; ++n) e.u.row(n) += du.segment<3>(3 * n).transpose();
    return e;
  }
};

double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).norm() / b.norm(); }

}  // namespace

TEST_SUITE("tools/springs") {
  TEST_CASE("the springs solve (diag(1/k) + W C W^T) f = T - X - W u0 and pull the final positions by f") {
    Setup t;
    const Setup::Expected e = t.expected();
    Eigen::MatrixX3d u = t.u0, f = t.f0;
    tools::SpringCache cache;
    CHECK(tools::solve_implicit_springs(t.system(), t.specs, t.states, cache, u, f, 5) == 4);
    CHECK(rel(u, e.u) <= 1e-12);
    CHECK(e.f.norm() > 1e-3);  // the springs do work
    // The forces, measured on the final positions, are the solved f: the
    // spring law holds at the end of the frame, not only in the solve.
    const tools::ToolState& s = t.states[0];
    Eigen::MatrixX3d node_f = Eigen::MatrixX3d::Zero(5, 3);
    V total = V::Zero();
    for (int p = 0; p < 2; ++p)
      for (int j = 0; j < 3; ++j) {
        const int n = s.grip[size_t(p)].nodes[size_t(j)];
        if (n == 4) continue;
        node_f.row(n) += s.grip[size_t(p)].weights(j) * e.f.segment<3>(3 * p).transpose();
        total += s.grip[size_t(p)].weights(j) * e.f.segment<3>(3 * p);
      }
    CHECK(rel(f - t.f0, node_f) <= 1e-9);
    REQUIRE(s.forces.size() == 5);
    for (int n = 0; n < 5; ++n) CHECK((s.forces[size_t(n)] - node_f.row(n).transpose()).norm() <= 1e-9 * node_f.norm());
    CHECK(s.forces[4].isZero());  // the fixed node's share goes into the support
    CHECK((s.total_force - total).norm() <= 1e-9 * total.norm());
  }

  TEST_CASE("a node of a piece cut free enters at its held displacement") {
    Setup t;
    const V h(0.004, -0.002, 0.003);
    t.held = [h](int n) { return n == 3 ? h : V::Zero(); };
    Eigen::MatrixX3d u = t.u0, f = t.f0;
    tools::SpringCache cache;
    tools::solve_implicit_springs(t.system(), t.specs, t.states, cache, u, f, 5);
    CHECK(rel(u, t.expected(h).u) <= 1e-12);
    CHECK(rel(u, t.expected().u) > 1e-3);  // and it matters
  }

  TEST_CASE("the responses are kept while the grasped nodes and the system stay, and rebuilt when either changes") {
    Setup t;
    tools::SpringCache cache;
    auto frame = [&] {
      Eigen::MatrixX3d u = t.u0, f = t.f0;
      tools::solve_implicit_springs(t.system(), t.specs, t.states, cache, u, f, 5);
      return u;
    };
    const Eigen::MatrixX3d first = frame();
    CHECK(frame() == first);
    CHECK(t.response_calls == 1);
    CHECK(cache.builds == 1);
    t.generation = 4;  // cutting changed the system
    CHECK(frame() == first);
    CHECK(t.response_calls == 2);
    t.states[0].grip[0].nodes = {1, 2, 3};  // the jaw slipped off node 0: another grasped node set
    frame();
    CHECK(t.response_calls == 3);
    CHECK(cache.nodes == std::vector<int>{1, 2, 3});
    cache.enabled = false;  // measuring the cache: every frame rebuilds
    frame();
    frame();
    CHECK(t.response_calls == 5);
    CHECK(cache.builds == 5);
  }

  TEST_CASE("nothing to hold: no grasper, an explicit spring or an empty grip changes nothing") {
    Setup t;
    tools::SpringCache cache;
    Eigen::MatrixX3d u = t.u0, f = t.f0;
    t.specs[0].implicit = false;
    CHECK(tools::solve_implicit_springs(t.system(), t.specs, t.states, cache, u, f, 5) == 0);
    t.specs[0].implicit = true;
    t.states[0].grip.clear();
    CHECK(tools::solve_implicit_springs(t.system(), t.specs, t.states, cache, u, f, 5) == 0);
    CHECK(u == t.u0);
    CHECK(f == t.f0);
    CHECK(t.response_calls == 0);
  }

  TEST_CASE("a grip that makes the point system singular is a clear error naming the frame") {
    Setup t;
    t.C.setZero();            // no compliance: A = I / k ...
    t.specs[0].stiffness = -1;  // ... with k < 0 is negative definite
    tools::SpringCache cache;
    Eigen::MatrixX3d u = t.u0, f = t.f0;
    std::string msg;
    try {
      tools::solve_implicit_springs(t.system(), t.specs, t.states, cache, u, f, 5);
    } catch (const softcut::Error& e) {
      msg = e.what();
    }
    CHECK(contains(msg, "frame 5: the implicit grasper springs give a singular system"));
    CHECK(cache.grip_key.empty());  // nothing half-kept: the next frame tries again
  }
}
