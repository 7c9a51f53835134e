#include "gpu/block_system.hpp"

#include <doctest/doctest.h>

#include <random>

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "mesh/generate/box.hpp"

namespace {

// Stiffness of a jittered box with the x = 0 face fixed, and a random SPD
// dense corner on the last `dense_nodes` nodes.
struct System {
  Eigen::SparseMatrix<double> K;
  Eigen::MatrixXd D;
};

System make_system(int cells, int dense_nodes, unsigned seed) {
  softcut::mesh::BoxOptions o;
  o.nx = cells + 1;
  o.ny = o.nz = cells;
  o.jitter = 0.2;
  o.seed = seed;
  const auto m = softcut::mesh::generate_box(o);
  const std::vector<softcut::fem::Material> mats(size_t(m.num_tets()), {1e4, 0.3});
  std::vector<char> free(size_t(m.num_nodes()), 1);
  for (int i = 0; i < m.num_nodes(); ++i) free[size_t(i)] = m.nodes(i, 0) > 1e-12;
  const auto map = softcut::fem::make_dof_map(free);
  System s;
  s.K = softcut::fem::restrict_matrix(softcut::fem::assemble_stiffness(m, mats), map);
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Eigen::MatrixXd G(3 * dense_nodes, 3 * dense_nodes);
  for (Eigen::Index i = 0; i < G.size(); ++i) G.data()[i] = g(rng);
  s.D = 1e2 * G * G.transpose();
  return s;
}

}  // namespace

TEST_SUITE("gpu/block_system") {
  TEST_CASE("block rows reproduce the sparse product plus the dense corner") {
    for (unsigned seed = 1; seed <= 4; ++seed) {
      const System s = make_system(2 + int(seed % 2), int(seed), seed);
      const auto bs = softcut::gpu::make_block_system(s.K, &s.D);
      CHECK(bs.size() == s.K.rows());
      CHECK(bs.dense_offset == s.K.rows() - s.D.rows());
      const Eigen::VectorXd x = Eigen::VectorXd::Random(s.K.rows());
      Eigen::VectorXd expected = s.K * x;
      expected.tail(s.D.rows()) += s.D * x.tail(s.D.rows());
      Eigen::VectorXd y;
      bs.apply(x, y);
      CHECK((y - expected).norm() <= 1e-12 * expected.norm());
    }
  }

  TEST_CASE("diagonal inverses invert the diagonal blocks of K + D") {
    const System s = make_system(2, 2, 7);
    const auto bs = softcut::gpu::make_block_system(s.K, &s.D);
    Eigen::MatrixXd A = Eigen::MatrixXd(s.K);
    A.bottomRightCorner(s.D.rows(), s.D.cols()) += s.D;
    for (int I = 0; I < bs.num_blocks; ++I) {
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> inv(bs.diag_inverse.data() + 9 * I);
      const Eigen::Matrix3d prod = inv * A.block<3, 3>(3 * I, 3 * I);
      CHECK((prod - Eigen::Matrix3d::Identity()).norm() < 1e-10);
    }
  }

  TEST_CASE("bad shapes and empty blocks are errors") {
    Eigen::SparseMatrix<double> K(4, 4);
    CHECK_THROWS_AS(softcut::gpu::make_block_system(K), softcut::Error);
    Eigen::SparseMatrix<double> Z(6, 6);
    Z.insert(0, 0) = 1;
    Z.insert(1, 1) = 1;
    Z.insert(2, 2) = 1;
    CHECK_THROWS_WITH_AS(softcut::gpu::make_block_system(Z), doctest::Contains("node block 1"), softcut::Error);
  }
}
