#include "fem/dof_map.hpp"

#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <random>

#include "core/error.hpp"
#include "fem_fixtures.hpp"

using namespace softcut;

TEST_SUITE("fem/dof_map") {
  TEST_CASE("restrict and expand round trip, and restrict_matrix selects rows and columns") {
    std::mt19937 rng(4);
    for (int trial = 0; trial < 20; ++trial) {
      const mesh::TetMesh m = test::jittered_box(2, 2, 2, 0.2, unsigned(trial) + 1);
      const int nn = m.num_nodes();
      std::vector<char> free_a(static_cast<size_t>(nn)), free_b(static_cast<size_t>(nn));
      for (int i = 0; i < nn; ++i) {
        free_a[size_t(i)] = rng() % 3 != 0;
        free_b[size_t(i)] = rng() % 2 != 0;
      }
      const fem::DofMap a = fem::make_dof_map(free_a), b = fem::make_dof_map(free_b);
      int nfree = 0;
      for (char c : free_a) nfree += c;
      CHECK(a.size() == 3 * nfree);
      for (int i = 0; i < a.size(); ++i) {
        CHECK(a.reduced[size_t(a.global[size_t(i)])] == i);
        if (i > 0) CHECK(a.global[size_t(i)] > a.global[size_t(i) - 1]);
      }
      const Eigen::VectorXd full = Eigen::VectorXd::Random(3 * nn);
      const Eigen::VectorXd red = fem::restrict_vector(full, a);
      const Eigen::VectorXd back = fem::expand_vector(red, a, nn);
      for (int d = 0; d < 3 * nn; ++d) CHECK(back(d) == (free_a[size_t(d / 3)] ? full(d) : 0.0));
      CHECK(fem::restrict_vector(back, a) == red);

      const fem::SparseMatrix K = fem::assemble_stiffness(m, test::random_materials(m.num_tets(), 2));
      const Eigen::MatrixXd Kd(K);
      const Eigen::MatrixXd Rab(fem::restrict_matrix(K, a, b));
      REQUIRE(Rab.rows() == a.size());
      REQUIRE(Rab.cols() == b.size());
      double err = 0;
      for (int i = 0; i < a.size(); ++i)
        for (int j = 0; j < b.size(); ++j) err = std::max(err, std::abs(Rab(i, j) - Kd(a.global[size_t(i)], b.global[size_t(j)])));
      CHECK(err == 0.0);
      CHECK(Eigen::MatrixXd(fem::restrict_matrix(K, a)) == Eigen::MatrixXd(fem::restrict_matrix(K, a, a)));
      // The restricted product equals the product of the expanded vector.
      const Eigen::VectorXd x = Eigen::VectorXd::Random(b.size());
      CHECK((Rab * x - fem::restrict_vector(Kd * fem::expand_vector(x, b, nn), a)).norm() <= 1e-12 * Kd.norm() * x.norm());
    }
  }

  TEST_CASE("flatten and unflatten round trip") {
    const Eigen::MatrixX3d f = Eigen::MatrixX3d::Random(7, 3);
    const Eigen::VectorXd v = fem::flatten(f);
    CHECK(v(3 * 4 + 2) == f(4, 2));
    CHECK(fem::unflatten(v) == f);
  }

  TEST_CASE("size mismatches are errors") {
    const fem::DofMap a = fem::make_dof_map({1, 0, 1});
    CHECK_THROWS_AS(fem::restrict_vector(Eigen::VectorXd::Zero(6), a), Error);
    CHECK_THROWS_AS(fem::expand_vector(Eigen::VectorXd::Zero(5), a, 3), Error);
    CHECK_THROWS_AS(fem::restrict_matrix(fem::SparseMatrix(6, 6), a), Error);
    CHECK_THROWS_AS(fem::unflatten(Eigen::VectorXd::Zero(4)), Error);
  }
}
