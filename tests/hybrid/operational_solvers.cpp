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
}
