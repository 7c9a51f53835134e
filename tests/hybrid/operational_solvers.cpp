#include "hybrid/operational_solvers.hpp"

#include <doctest/doctest.h>

#include <Eigen/Dense>
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
    // A hand-made 30-unknown system Q diag(lambda) Q^T, Q a random rotation:
    // eigenvalues in [1, 2] (the inverse's product is exact to ~1e-15, no
    // refinement), or spanning 10 decades (its product misses by ~cond eps,
    // far above 1e-12: one refinement through the LL' factor brings it to
    // what that factor's own solve reaches). The reported residual is the true one.
    for (const bool ill : {false, true}) {
      CAPTURE(ill);
      std::mt19937 rng(5);
      std::uniform_real_distribution<double> u(-1, 1);
      const int n = 30;
      Eigen::MatrixXd M(n, n);
      for (Eigen::Index k = 0; k < M.size(); ++k) M(k) = u(rng);
      const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(M).householderQ();
      Eigen::VectorXd lambda(n);
      for (int i = 0; i < n; ++i) lambda[i] = ill ? std::pow(10.0, -10.0 * i / (n - 1)) : 1.0 + double(i) / n;
      Eigen::MatrixXd A = Q * lambda.asDiagonal() * Q.transpose();
      A = 0.5 * (A + A.transpose()).eval();
      OperationalSystem sys;
      for (int v = 0; v < n / 3; ++v) sys.nodes.push_back(v), sys.node_index.push_back(v);
      sys.num_operational = n / 3;
      sys.K = A.sparseView();
      sys.K_prime = std::make_shared<const Eigen::MatrixXd>(0, 0);
      sys.generation = ill ? 1001 : 1000;
      CholmodSolver dense;
      const Eigen::VectorXd b = Eigen::VectorXd::Random(n);
      Eigen::VectorXd x;
      const SolveReport r = dense.solve(sys, b, x);
      CHECK(dense.uses_dense());
      const double truth = (A * x - b).norm() / b.norm();
      CHECK(r.relative_residual == doctest::Approx(truth).epsilon(1e-6));
      CHECK(r.iterations == (ill ? 1 : 0));
      if (!ill) CHECK(truth <= 1e-12);
      const Eigen::VectorXd x_llt = Eigen::LLT<Eigen::MatrixXd>(A).solve(b);
      CHECK(truth <= 100 * (A * x_llt - b).norm() / b.norm() + 1e-15);
    }
  }

  TEST_CASE("the dense path reads only the columns where b is nonzero, with or without the helper thread") {
    // A hand-made SPD system of 150 unknowns; right-hand sides nonzero on a
    // few runs (a frame's loads and P'), on more than 3/4 of the entries (the
    // symmetric product) and on none. Each against Eigen's LL' solve; the
    // helper thread's solve gives the same bits as the caller's alone.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    const int n = 150;
    Eigen::MatrixXd R(n, n);
    for (Eigen::Index k = 0; k < R.size(); ++k) R(k) = u(rng);
    const Eigen::MatrixXd A = R * R.transpose() + n * Eigen::MatrixXd::Identity(n, n);
    OperationalSystem sys;
    for (int v = 0; v < n / 3; ++v) sys.nodes.push_back(v), sys.node_index.push_back(v);
    sys.num_operational = n / 3;
    sys.K = A.sparseView();
    sys.K_prime = std::make_shared<const Eigen::MatrixXd>(0, 0);
    sys.generation = 2000;
    CholmodSolver alone, helped;
    helped.share_helper(std::make_shared<HelperThread>());
    const Eigen::LLT<Eigen::MatrixXd> llt(A);
    for (const int filled : {1, 12, 100, 120, 150}) {
      CAPTURE(filled);
      Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
      for (int k = 0; k < filled; ++k) b[(k * 37 + (k % 5)) % n] = u(rng);  // scattered entries and runs
      b[n - 1] = 1.0;
      Eigen::VectorXd x1, x2;
      const SolveReport r1 = alone.solve(sys, b, x1), r2 = helped.solve(sys, b, x2);
      CHECK(alone.uses_dense());
      CHECK(r1.relative_residual <= 1e-12);
      CHECK((x1 - llt.solve(b)).norm() <= 1e-12 * x1.norm());
      CHECK(r2.relative_residual == r1.relative_residual);
      CHECK((x1.array() == x2.array()).all());
    }
    Eigen::VectorXd x;
    CHECK(alone.solve(sys, Eigen::VectorXd::Zero(n), x).relative_residual == 0);
    CHECK(x.isZero(0));
  }
}
