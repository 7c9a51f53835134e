#include "hybrid/operational_solvers.hpp"

#include <doctest/doctest.h>

#include <random>

#include "fixtures.hpp"
#include "hybrid/precompute.hpp"

using namespace softcut;
using namespace softcut::hybrid;

TEST_SUITE("hybrid/operational_solvers") {
  TEST_CASE("CG and CHOLMOD backends agree and a CG warm start needs fewer iterations") {
    std::mt19937 rng(13);
    test::HybridCase c;
    do c = test::random_case(rng, 0, 4); while (c.partition.operational.size() < 6 || c.partition.interface.empty());
    const Model M = precompute(c.mesh, c.material, c.partition, {});
    const OperationalSystem& sys = *M.operational;
    const Eigen::VectorXd b = Eigen::VectorXd::Random(sys.size());
    solve::CgOptions o;
    o.tolerance = 1e-12;
    CgSolver cg(o);
    CholmodSolver direct;
    Eigen::VectorXd x1, x2;
    const SolveReport r1 = cg.solve(sys, b, x1);
    direct.solve(sys, b, x2);
    CHECK((x1 - x2).norm() <= 1e-9 * x2.norm());
    CgSolver block(o, CgPreconditioner::interface_block);
    Eigen::VectorXd x3;
    const SolveReport r3 = block.solve(sys, b, x3);
    CHECK((x3 - x2).norm() <= 1e-9 * x2.norm());
    CHECK(r3.iterations < r1.iterations);  // the exact interface block cuts iterations
    const Eigen::VectorXd b2 = b + 1e-3 * Eigen::VectorXd::Random(sys.size());
    const SolveReport r2 = cg.solve(sys, b2, x1);
    CHECK(r2.iterations < r1.iterations);
    CHECK(r2.relative_residual <= 1e-12);
  }

  TEST_CASE("the CHOLMOD backend's dense path for small systems solves as its sparse one") {
    std::mt19937 rng(72);
    int checked = 0;
    for (int trial = 0; trial < 12; ++trial) {
      const test::HybridCase c = test::random_case(rng, trial % 4, 3);
      const Model M = precompute(c.mesh, c.material, c.partition, {});
      const OperationalSystem& sys = *M.operational;
      if (sys.size() == 0) continue;
      CholmodSolver sparse(false), either;
      const Eigen::VectorXd b = Eigen::VectorXd::Random(sys.size());
      Eigen::VectorXd x1, x2;
      const SolveReport r1 = sparse.solve(sys, b, x1), r2 = either.solve(sys, b, x2);
      CHECK(!sparse.uses_dense());
      CHECK(either.uses_dense() == (sys.size() <= 500));
      CHECK(r1.relative_residual <= 1e-12);
      CHECK(r2.relative_residual <= 1e-12);
      CHECK((x1 - x2).norm() <= 1e-10 * x1.norm());
      ++checked;
    }
    CHECK(checked >= 6);
  }

  TEST_CASE("the dense path multiplies by the kept inverse and refines where that is not exact enough") {
    // A hand-made 30-unknown system D S D, S random SPD, D spanning `spread`
    // decades: well conditioned, the inverse's product already has a residual
    // below 1e-12; badly conditioned, one refinement step through the LL'
    // factor brings it there.
    for (const double spread : {0.0, 5.0}) {
      CAPTURE(spread);
      std::mt19937 rng(5);
      std::uniform_real_distribution<double> u(-1, 1);
      const int n = 30;
      Eigen::MatrixXd M(n, n);
      for (Eigen::Index k = 0; k < M.size(); ++k) M(k) = u(rng);
      Eigen::VectorXd d(n);
      for (int i = 0; i < n; ++i) d[i] = std::pow(10.0, -spread * i / (n - 1));
      const Eigen::MatrixXd A = d.asDiagonal() * (M * M.transpose() + n * Eigen::MatrixXd::Identity(n, n)) * d.asDiagonal();
      OperationalSystem sys;
      for (int v = 0; v < n / 3; ++v) sys.nodes.push_back(v), sys.node_index.push_back(v);
      sys.num_operational = n / 3;
      sys.K = A.sparseView();
      sys.K_prime = std::make_shared<const Eigen::MatrixXd>(0, 0);
      sys.generation = 1000 + long(spread);
      CholmodSolver dense;
      const Eigen::VectorXd b = Eigen::VectorXd::Random(n);
      Eigen::VectorXd x;
      const SolveReport r = dense.solve(sys, b, x);
      CHECK(dense.uses_dense());
      CHECK(r.relative_residual <= 1e-12);
      CHECK((A * x - b).norm() <= 1e-12 * b.norm());  // the reported residual is the true one
      CHECK(r.iterations == (spread > 0 ? 1 : 0));
    }
  }
}
