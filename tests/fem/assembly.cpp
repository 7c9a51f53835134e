#include "fem/assembly.hpp"

#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>

#include "core/error.hpp"
#include "fem/dof_map.hpp"
#include "fem/element_stiffness.hpp"
#include "fem/strain.hpp"
#include "fem_fixtures.hpp"

using namespace softcut;

namespace {

// Dense assembly straight from the definition, for small meshes.
Eigen::MatrixXd dense_assembly(const mesh::TetMesh& m, const std::vector<fem::Material>& mats,
                               const std::vector<int>& tets) {
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * m.num_nodes(), 3 * m.num_nodes());
  for (int t : tets) {
    const fem::Mat12 Ke = fem::element_stiffness(fem::tet_corners(m, t), mats[size_t(t)]);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) K.block<3, 3>(3 * m.tets(t, a), 3 * m.tets(t, b)) += Ke.block<3, 3>(3 * a, 3 * b);
  }
  return K;
}

bool same_bits(const fem::SparseMatrix& A, const fem::SparseMatrix& B) {
  if (A.nonZeros() != B.nonZeros() || A.rows() != B.rows()) return false;
  for (int j = 0; j <= A.cols(); ++j)
    if (A.outerIndexPtr()[j] != B.outerIndexPtr()[j]) return false;
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k)
    if (A.innerIndexPtr()[k] != B.innerIndexPtr()[k] || A.valuePtr()[k] != B.valuePtr()[k]) return false;
  return true;
}

}  // namespace

TEST_SUITE("fem/assembly") {
  TEST_CASE("equals a naive dense assembly on random meshes and tet subsets, any thread count") {
    for (unsigned seed = 1; seed <= 12; ++seed) {
      const mesh::TetMesh m = test::jittered_box(1 + seed % 3, 2, 1 + seed % 2, 0.2, seed);
      const auto mats = test::random_materials(m.num_tets(), seed);
      const std::vector<int> tets = seed % 4 == 0 ? std::vector<int>{} : test::random_subset(m.num_tets(), 0.5, seed);
      std::vector<int> all(size_t(m.num_tets()));
      for (int t = 0; t < m.num_tets(); ++t) all[size_t(t)] = t;
      const Eigen::MatrixXd ref = dense_assembly(m, mats, tets.empty() ? all : tets);
      const fem::SparseMatrix K1 = fem::assemble_stiffness(m, mats, tets, 1);
      CAPTURE(seed);
      CHECK((Eigen::MatrixXd(K1) - ref).norm() <= 1e-14 * ref.norm());
      CHECK((Eigen::MatrixXd(fem::assemble_stiffness_triplets(m, mats, tets)) - ref).norm() <= 1e-14 * ref.norm());
      for (int threads : {2, 3, 5}) CHECK(same_bits(fem::assemble_stiffness(m, mats, tets, threads), K1));
      // The pattern is exactly the nonzero 3x3 node blocks: none missing (the
      // norm check) and none extra (nodes outside the subset stay empty).
      int blocks = 0;
      for (int i = 0; i < m.num_nodes(); ++i)
        for (int j = 0; j < m.num_nodes(); ++j) blocks += ref.block<3, 3>(3 * i, 3 * j).norm() > 0;
      CHECK(K1.nonZeros() == 9 * blocks);
    }
  }

  TEST_CASE("threaded assembly of a larger mesh is bit-identical to the serial one") {
    const mesh::TetMesh m = test::jittered_box(16, 12, 10, 0.2, 3);  // 11520 tets
    const auto mats = test::random_materials(m.num_tets(), 3);
    const fem::SparseMatrix K1 = fem::assemble_stiffness(m, mats, {}, 1);
    CHECK(same_bits(fem::assemble_stiffness(m, mats, {}, 2), K1));
    CHECK(same_bits(fem::assemble_stiffness(m, mats, {}, 4), K1));
    const fem::SparseMatrix Kt = fem::assemble_stiffness_triplets(m, mats);
    CHECK((K1 - Kt).norm() <= 1e-14 * Kt.norm());
  }

  TEST_CASE("node blocks of a node subset equal the assembled matrix's rows and columns bit for bit") {
    for (unsigned seed = 1; seed <= 10; ++seed) {
      const mesh::TetMesh m = test::jittered_box(2 + seed % 3, 3, 2, 0.2, seed);
      const auto mats = test::random_materials(m.num_tets(), seed);
      const std::vector<int> tets = test::random_subset(m.num_tets(), 0.6, seed);
      // A random subset of the nodes in a random order.
      std::mt19937 rng(seed);
      std::vector<int> nodes(size_t(m.num_nodes()));
      for (int v = 0; v < m.num_nodes(); ++v) nodes[size_t(v)] = v;
      std::shuffle(nodes.begin(), nodes.end(), rng);
      nodes.resize(nodes.size() * 2 / 3);
      std::vector<int> position(size_t(m.num_nodes()), -1);
      for (size_t k = 0; k < nodes.size(); ++k) position[size_t(nodes[k])] = int(k);
      const fem::BlockStiffness B = fem::assemble_node_blocks(m, mats, tets, position, int(nodes.size()), 1);
      const fem::SparseMatrix K = B.to_sparse();
      CHECK(same_bits(fem::assemble_node_blocks(m, mats, tets, position, int(nodes.size()), 2).to_sparse(), K));
      CAPTURE(seed);
      // Reference: the whole assembled matrix, its subset's entries copied.
      const fem::SparseMatrix full = fem::assemble_stiffness(m, mats, tets, 1);
      const Eigen::Index n = 3 * Eigen::Index(nodes.size());
      Eigen::MatrixXd ref = Eigen::MatrixXd::Zero(n, n);
      Eigen::MatrixXi stored = Eigen::MatrixXi::Zero(n, n);
      for (int col = 0; col < full.outerSize(); ++col)
        for (fem::SparseMatrix::InnerIterator it(full, col); it; ++it) {
          const int i = position[size_t(it.row() / 3)], j = position[size_t(col / 3)];
          if (i < 0 || j < 0) continue;
          ref(3 * i + it.row() % 3, 3 * j + col % 3) = it.value();
          stored(3 * i + it.row() % 3, 3 * j + col % 3) = 1;
        }
      REQUIRE(K.rows() == n);
      CHECK(K.nonZeros() == stored.sum());  // the same pattern, structural zeros included
      CHECK((Eigen::MatrixXd(K).array() == ref.array()).all());
      for (int j = 0; j < B.nodes(); ++j) {
        CHECK(std::is_sorted(B.col.begin() + B.row_start[size_t(j)], B.col.begin() + B.row_start[size_t(j) + 1]));
        for (int k = B.row_start[size_t(j)]; k < B.row_start[size_t(j) + 1]; ++k)
          CHECK(B.blocks[size_t(k)] == ref.block<3, 3>(3 * j, 3 * B.col[size_t(k)]));
      }
    }
    const mesh::TetMesh m = test::jittered_box(1, 1, 1, 0, 1);
    const auto mats = test::random_materials(m.num_tets(), 1);
    CHECK_THROWS_WITH_AS(fem::assemble_node_blocks(m, mats, {}, std::vector<int>(3, 0), 1),
                         doctest::Contains("3 node positions for a mesh of"), Error);
    CHECK_THROWS_WITH_AS(fem::assemble_node_blocks(m, mats, {}, std::vector<int>(size_t(m.num_nodes()), 2), 2),
                         doctest::Contains("node position 2 outside -1..1"), Error);
  }

  TEST_CASE("an unconstrained body has exactly six zero eigenvalues (the rigid motions)") {
    for (unsigned seed = 1; seed <= 3; ++seed) {
      const mesh::TetMesh m = test::jittered_box(2, 2, 1 + int(seed) % 2, 0.2, seed);
      const auto mats = test::random_materials(m.num_tets(), seed);
      const Eigen::MatrixXd K(fem::assemble_stiffness(m, mats));
      CHECK((K - K.transpose()).norm() == 0.0);
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(K);
      const Eigen::VectorXd ev = es.eigenvalues();
      const double top = ev(ev.size() - 1);
      CAPTURE(ev.head(8).transpose() / top);
      for (int i = 0; i < 6; ++i) CHECK(std::abs(ev(i)) <= 1e-12 * top);
      // Coarse jittered box, materials spanning 100x: the softest bending
      // mode sits near 1e-3 of the top; round-off zeros near 1e-16.
      CHECK(ev(6) >= 1e-5 * top);
      const Eigen::MatrixXd R = test::rigid_motions(m.nodes);
      CHECK((K * R).norm() <= 1e-12 * top * R.norm());
    }
  }

  TEST_CASE("1/2 u^T K u equals the element-wise strain energy") {
    const mesh::TetMesh m = test::jittered_box(3, 3, 2, 0.2, 8);
    const auto mats = test::random_materials(m.num_tets(), 8);
    const fem::SparseMatrix K = fem::assemble_stiffness(m, mats);
    const Eigen::MatrixX3d u = 1e-3 * Eigen::MatrixX3d::Random(m.num_nodes(), 3);
    Eigen::VectorXd v(3 * m.num_nodes());
    for (int i = 0; i < m.num_nodes(); ++i) v.segment<3>(3 * i) = u.row(i).transpose();
    CHECK(0.5 * v.dot(K * v) == doctest::Approx(fem::strain_energy(m, mats, u)).epsilon(1e-12));
  }

  TEST_CASE("initial strain forces do the virtual work of the initial stress: f0 . u = sum V eps(u) . D eps0") {
    std::mt19937 rng(9);
    std::normal_distribution<double> g(0, 1);
    for (unsigned seed = 1; seed <= 3; ++seed) {
      const mesh::TetMesh m = test::jittered_box(3, 2, 2, 0.2, seed);
      auto mats = test::random_materials(m.num_tets(), seed);
      std::vector<int> subset;
      for (int t = 0; t < m.num_tets(); ++t) {
        if (t % 3 == 0) continue;  // some tets without
        for (double& e : mats[size_t(t)].initial_strain) e = 0.01 * g(rng);
        if (t % 2) subset.push_back(t);
      }
      const Eigen::MatrixX3d u = Eigen::MatrixX3d::Random(m.num_nodes(), 3);
      const fem::StrainField eps = fem::element_strains(m, u);
      for (const std::vector<int>& tets : {std::vector<int>{}, subset}) {
        double work = 0;
        for (int t = 0; t < m.num_tets(); ++t) {
          if (!tets.empty() && !std::count(tets.begin(), tets.end(), t)) continue;
          const auto& mat = mats[size_t(t)];
          const Eigen::Matrix<double, 6, 1> e0 = Eigen::Map<const Eigen::Matrix<double, 6, 1>>(mat.initial_strain.data());
          work += mesh::signed_volume(m, t) * eps.row(t).dot(fem::elasticity_matrix(mat) * e0);
        }
        const Eigen::MatrixX3d f0 = fem::element_loads(m, mats, tets);
        CAPTURE(seed);
        CHECK(std::abs(work) > 0);
        CHECK(fem::flatten(f0).dot(fem::flatten(u)) == doctest::Approx(work).epsilon(1e-12));
        // A constant stress has no net force or moment on a free body.
        CHECK((test::rigid_motions(m.nodes).transpose() * fem::flatten(f0)).norm() <= 1e-12 * fem::flatten(f0).norm());
      }
    }
  }

  TEST_CASE("a bad initial strain is refused with the tet and the component named") {
    const mesh::TetMesh m = test::jittered_box(1, 1, 1, 0, 1);
    auto mats = test::random_materials(m.num_tets(), 1);
    mats[2].initial_strain[4] = std::nan("");
    CHECK_THROWS_WITH_AS(fem::element_loads(m, mats), doctest::Contains("tetrahedron 2"), Error);
    CHECK_THROWS_WITH_AS(fem::assemble_stiffness(m, mats), doctest::Contains("component eps_zx"), Error);
    mats[2].initial_strain[0] = 0.7;
    mats[2].initial_strain[4] = 0.0;
    CHECK_THROWS_WITH_AS(fem::element_loads(m, mats), doctest::Contains("eps_xx must be a finite number within +-0.5"), Error);
    mats[2].initial_strain[0] = 0.5;
    mats[2].initial_strain[4] = 1.2;  // engineering shear: eps_zx = 0.6, named as the tensor value
    CHECK_THROWS_WITH_AS(fem::element_loads(m, mats), doctest::Contains("eps_zx must be a finite number within +-0.5 (a small-strain model), got 0.6"), Error);
    mats[2].initial_strain[4] = 1.0;  // eps_zx = 0.5: the limit
    CHECK(fem::flatten(fem::element_loads(m, mats)).norm() > 0);
    CHECK(!fem::any_element_load(test::random_materials(m.num_tets(), 1)));
  }

  TEST_CASE("bad input is refused with the tet named") {
    mesh::TetMesh m = test::jittered_box(1, 1, 1, 0, 1);
    auto mats = test::random_materials(m.num_tets(), 1);
    CHECK_THROWS_WITH_AS(fem::assemble_stiffness(m, std::vector<fem::Material>(2)),
                         doctest::Contains("2 materials for 6 tetrahedra"), Error);
    CHECK_THROWS_WITH_AS(fem::assemble_stiffness(m, mats, {0, 6}), doctest::Contains("tet id 6"), Error);
    mats[3].poisson = 0.5;
    CHECK_THROWS_WITH_AS(fem::assemble_stiffness(m, mats), doctest::Contains("tetrahedron 3"), Error);
    mats[3].poisson = 0.3;
    std::swap(m.tets(4, 2), m.tets(4, 3));  // inverted
    CHECK_THROWS_WITH_AS(fem::assemble_stiffness(m, mats), doctest::Contains("tetrahedron 4"), Error);
    CHECK_THROWS_WITH_AS(fem::assemble_stiffness_triplets(m, mats), doctest::Contains("inverted"), Error);
    std::swap(m.tets(4, 2), m.tets(4, 3));
    m.tets(1, 0) = 99;
    CHECK_THROWS_WITH_AS(fem::assemble_stiffness(m, mats), doctest::Contains("node 99"), Error);
  }
}
