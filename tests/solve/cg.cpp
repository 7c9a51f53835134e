#include "solve/cg.hpp"

#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <cmath>

#include "core/error.hpp"
#include "solve/cholesky.hpp"
#include "spd_fixtures.hpp"

using namespace softcut;

namespace {

// One solve with a workspace of its own (every solve takes one).
Eigen::MatrixXd solved(const solve::Cholesky& c, const Eigen::MatrixXd& B) {
  solve::SolveWorkspace ws;
  return c.solve(B, ws);
}

solve::BlockJacobi jacobi(const Eigen::SparseMatrix<double>& A) {
  solve::BlockJacobi pre(A);
  pre.finalize();
  return pre;
}

}  // namespace

TEST_SUITE("solve/cg") {
  TEST_CASE("CG with block Jacobi agrees with CHOLMOD to the CG tolerance") {
    for (unsigned seed = 1; seed <= 6; ++seed) {
      const int n = 4 + int(seed) % 4;
      const Eigen::SparseMatrix<double> A = test::grid_spd(n, seed);
      const Eigen::VectorXd b = Eigen::VectorXd::Random(A.rows());
      const Eigen::VectorXd ref = solved(solve::Cholesky(A), b);
      const solve::BlockJacobi pre = jacobi(A);
      for (double tol : {1e-6, 1e-10}) {
        Eigen::VectorXd x;
        const solve::CgResult r = solve::pcg(solve::sparse_operator(A), pre.as_operator(), b, x, {tol, 0});
        CAPTURE(seed);
        CAPTURE(tol);
        CHECK(r.converged);
        CHECK(r.iterations > 0);
        CHECK(r.relative_residual <= tol);
        // ||A (x - ref)|| = true residual of x; the recursive one CG stops on
        // drifts by round-off only, so 1.01 tol bounds it.
        CHECK((A * (x - ref)).norm() <= 1.01 * tol * b.norm());
      }
    }
  }

  TEST_CASE("a warm start at the solution takes zero iterations") {
    const Eigen::SparseMatrix<double> A = test::grid_spd(6, 3);
    const Eigen::VectorXd b = Eigen::VectorXd::Random(A.rows());
    Eigen::VectorXd x = solved(solve::Cholesky(A), b);
    const Eigen::VectorXd x0 = x;
    const solve::CgResult r = solve::pcg(solve::sparse_operator(A), jacobi(A).as_operator(), b, x, {1e-10, 0});
    CHECK(r.converged);
    CHECK(r.iterations == 0);
    CHECK(x == x0);
    // A nearby start converges in fewer iterations than a cold one.
    Eigen::VectorXd cold, warm = x0 + 1e-6 * Eigen::VectorXd::Random(x0.size());
    const auto rc = solve::pcg(solve::sparse_operator(A), jacobi(A).as_operator(), b, cold, {1e-10, 0});
    const auto rw = solve::pcg(solve::sparse_operator(A), jacobi(A).as_operator(), b, warm, {1e-10, 0});
    CHECK(rw.converged);
    CHECK(rw.iterations < rc.iterations);
  }

  TEST_CASE("too few iterations are reported as not converged, with the true residual") {
    const Eigen::SparseMatrix<double> A = test::grid_spd(7, 4);
    const Eigen::VectorXd b = Eigen::VectorXd::Random(A.rows());
    Eigen::VectorXd x;
    const solve::CgResult r = solve::pcg(solve::sparse_operator(A), jacobi(A).as_operator(), b, x, {1e-10, 5});
    CHECK_FALSE(r.converged);
    CHECK(r.iterations == 5);
    CHECK(r.relative_residual > 1e-10);
    CHECK(r.relative_residual == doctest::Approx((b - A * x).norm() / b.norm()).epsilon(1e-8));
  }

  TEST_CASE("zero right-hand side gives zero, and NaN inputs and indefinite operators are errors") {
    const Eigen::SparseMatrix<double> A = test::grid_spd(3, 1);
    const solve::BlockJacobi pre = jacobi(A);
    Eigen::VectorXd x = Eigen::VectorXd::Ones(A.rows());
    const auto r0 = solve::pcg(solve::sparse_operator(A), pre.as_operator(), Eigen::VectorXd::Zero(A.rows()), x);
    CHECK(r0.converged);
    CHECK(r0.iterations == 0);
    CHECK(x.isZero(0));

    Eigen::VectorXd b = Eigen::VectorXd::Ones(A.rows());
    b(7) = std::nan("");
    CHECK_THROWS_WITH_AS(solve::pcg(solve::sparse_operator(A), pre.as_operator(), b, x),
                         doctest::Contains("right-hand side has NaN"), Error);
    b(7) = 1;
    x = Eigen::VectorXd::Zero(A.rows());
    x(2) = INFINITY;
    CHECK_THROWS_WITH_AS(solve::pcg(solve::sparse_operator(A), pre.as_operator(), b, x),
                         doctest::Contains("warm start"), Error);

    const Eigen::SparseMatrix<double> neg = -A;
    Eigen::VectorXd y;
    CHECK_THROWS_WITH_AS(solve::pcg(solve::sparse_operator(neg), pre.as_operator(), b, y),
                         doctest::Contains("not positive definite"), Error);
  }

  TEST_CASE("block Jacobi is exact on a block-diagonal matrix and accepts a dense block") {
    Eigen::SparseMatrix<double> A = test::grid_spd(4, 6);
    Eigen::SparseMatrix<double> D(A.rows(), A.cols());
    std::vector<Eigen::Triplet<double>> trip;
    for (int k = 0; k < A.outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(A, k); it; ++it)
        if (it.row() / 3 == it.col() / 3) trip.emplace_back(int(it.row()), int(it.col()), it.value());
    D.setFromTriplets(trip.begin(), trip.end());
    const Eigen::VectorXd b = Eigen::VectorXd::Random(A.rows());
    Eigen::VectorXd x;
    const auto r = solve::pcg(solve::sparse_operator(D), jacobi(D).as_operator(), b, x, {1e-12, 0});
    CHECK(r.converged);
    CHECK(r.iterations == 1);

    // A dense symmetric block on DOFs [6, 6 + 9): the preconditioner built
    // from A plus add_dense equals the one built from the summed matrix.
    Eigen::MatrixXd M = Eigen::MatrixXd::Random(9, 9);
    M = (M * M.transpose()).eval();
    Eigen::MatrixXd Sd = Eigen::MatrixXd(A);
    Sd.block(6, 6, 9, 9) += M;
    solve::BlockJacobi p1(A);
    p1.add_dense(M, 6);
    p1.finalize();
    const solve::BlockJacobi p2 = jacobi(Eigen::SparseMatrix<double>(Sd.sparseView()));
    Eigen::VectorXd y1(A.rows()), y2(A.rows());
    p1.apply(b, y1);
    p2.apply(b, y2);
    CHECK((y1 - y2).norm() <= 1e-12 * y2.norm());
    CHECK_THROWS_AS(p1.add_dense(M, 4), Error);
    CHECK_THROWS_AS(p1.add_dense(Eigen::MatrixXd::Zero(9, 9), int(A.rows()) - 6), Error);
    CHECK_THROWS_AS(solve::BlockJacobi(Eigen::SparseMatrix<double>(4, 4)), Error);
    Eigen::VectorXd small(5);
    CHECK_THROWS_AS(p1.apply(b, small), Error);
  }
}
