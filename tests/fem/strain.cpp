// fem/strain: a tet's strain is the symmetric part of the displacement
// gradient (engineering shears), its stress D (eps - eps0), on distorted
// meshes against closed forms.
#include "fem/strain.hpp"

#include <doctest/doctest.h>

#include <random>

#include "core/error.hpp"
#include "fem_fixtures.hpp"
#include "test_support.hpp"

using namespace softcut;

TEST_SUITE("fem/strain") {
  TEST_CASE("a linear field gives its symmetric gradient in every tet, and the stress D (eps - eps0)") {
    std::mt19937 rng(5);
    std::normal_distribution<double> g(0, 1);
    for (unsigned seed = 1; seed <= 3; ++seed) {
      const mesh::TetMesh m = test::jittered_box(3, 3, 2, 0.24, seed);
      Eigen::Matrix3d A;
      for (int i = 0; i < 9; ++i) A(i) = 1e-3 * g(rng);
      Eigen::MatrixX3d u(m.num_nodes(), 3);
      for (int i = 0; i < m.num_nodes(); ++i) u.row(i) = (A * m.node(i)).transpose() + 1e-3 * Eigen::RowVector3d(1, 2, 3);  // plus a translation
      Eigen::Matrix<double, 1, 6> e;  // Voigt, engineering shears
      e << A(0, 0), A(1, 1), A(2, 2), A(1, 2) + A(2, 1), A(2, 0) + A(0, 2), A(0, 1) + A(1, 0);
      fem::Material mat{5e3, 0.3};
      mat.initial_strain = {1e-4, 0, -2e-4, 0, 3e-4, 0};
      const std::vector<fem::Material> mats(size_t(m.num_tets()), mat);
      const fem::StrainField eps = fem::element_strains(m, u);
      const fem::StrainField sig = fem::element_stresses(m, mats, u);
      const Eigen::Matrix<double, 6, 1> e0 = Eigen::Map<const Eigen::Matrix<double, 6, 1>>(mat.initial_strain.data());
      const Eigen::Matrix<double, 6, 1> s = fem::elasticity_matrix(mat) * (e.transpose() - e0);
      for (int t = 0; t < m.num_tets(); ++t) {
        CHECK((eps.row(t) - e).norm() <= 1e-12 * e.norm());
        CHECK((sig.row(t).transpose() - s).norm() <= 1e-9 * s.norm());
      }
    }
  }

  TEST_CASE("sizes that do not match are errors naming them") {
    const mesh::TetMesh m = test::jittered_box(2, 2, 2, 0, 1);
    CHECK(test::contains(test::error_of([&] { fem::element_strains(m, Eigen::MatrixX3d::Zero(3, 3)); }), "3 rows"));
    CHECK(test::contains(test::error_of([&] { fem::element_stresses(m, {}, Eigen::MatrixX3d::Zero(m.num_nodes(), 3)); }),
                         "0 materials"));
  }
}
