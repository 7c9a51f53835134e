#include "fem/element_stiffness.hpp"

#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <random>

#include "fem/assembly.hpp"
#include "fem_fixtures.hpp"

using namespace softcut;
using fem::Mat12;
using fem::TetCorners;
using Vec12 = Eigen::Matrix<double, 12, 1>;

namespace {

// A well-shaped random tet: a regular tet with corners moved by up to 20% of
// the edge, random scale (1 mm .. 1 m) and offset, positively oriented.
TetCorners random_tet(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  TetCorners X;
  X << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  const double scale = std::pow(10.0, -3 + 3 * (0.5 + 0.5 * u(rng)));
  for (int k = 0; k < 4; ++k)
    for (int c = 0; c < 3; ++c) X(k, c) = scale * (X(k, c) + 0.4 * u(rng));
  const Eigen::RowVector3d offset(u(rng), u(rng), u(rng));
  X.rowwise() += offset;
  if (mesh::signed_volume(X.row(0), X.row(1), X.row(2), X.row(3)) < 0) X.row(2).swap(X.row(3));
  return X;
}

fem::Material random_material(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  return {1e3 * std::pow(100.0, u(rng)), -0.5 + 0.95 * u(rng)};
}

// Strain energy from the displacement gradient grad u = Du Dm^-1 (no B, no D):
// V (mu eps:eps + lambda/2 tr(eps)^2).
double energy_from_gradient(const TetCorners& X, const fem::Material& mat, const Vec12& u) {
  Eigen::Matrix3d Dm, Du;
  for (int k = 0; k < 3; ++k) {
    Dm.col(k) = (X.row(k + 1) - X.row(0)).transpose();
    Du.col(k) = u.segment<3>(3 * (k + 1)) - u.segment<3>(0);
  }
  const Eigen::Matrix3d grad = Du * Dm.inverse();
  const Eigen::Matrix3d eps = 0.5 * (grad + grad.transpose());
  const double E = mat.young, nu = mat.poisson;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  return Dm.determinant() / 6.0 * (mu * eps.squaredNorm() + 0.5 * lambda * eps.trace() * eps.trace());
}

// strain_energy of a one-tet mesh.
double energy_of_assembly(const TetCorners& X, const fem::Material& mat, const Vec12& u) {
  mesh::TetMesh m;
  m.nodes = X;
  m.tets.resize(1, 4);
  m.tets << 0, 1, 2, 3;
  m.labels = Eigen::VectorXi::Zero(1);
  Eigen::MatrixX3d U(4, 3);
  for (int k = 0; k < 4; ++k) U.row(k) = u.segment<3>(3 * k).transpose();
  return fem::strain_energy(m, {mat}, U);
}

}  // namespace

TEST_SUITE("fem/element_stiffness") {
  TEST_CASE("K_e is symmetric and equals V B^T D B") {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 200; ++trial) {
      const TetCorners X = random_tet(rng);
      const fem::Material mat = random_material(rng);
      const Mat12 K = fem::element_stiffness(X, mat);
      double V = 0;
      const fem::Mat6x12 B = fem::strain_displacement(X, &V);
      const Mat12 ref = V * B.transpose() * fem::elasticity_matrix(mat) * B;
      CHECK(V > 0);
      CHECK((K - K.transpose()).norm() == 0.0);
      CHECK((K - ref).norm() <= 1e-13 * ref.norm());
    }
  }

  TEST_CASE("exactly six zero eigenvalues, spanned by the rigid motions") {
    std::mt19937 rng(11);
    for (int trial = 0; trial < 200; ++trial) {
      const TetCorners X = random_tet(rng);
      const Mat12 K = fem::element_stiffness(X, random_material(rng));
      Eigen::SelfAdjointEigenSolver<Mat12> es(K);
      const Vec12 ev = es.eigenvalues();  // ascending
      const double top = ev(11);
      CAPTURE(ev.transpose());
      for (int i = 0; i < 6; ++i) CHECK(std::abs(ev(i)) <= 1e-12 * top);
      // Well-shaped tets with nu <= 0.45: the softest deformation mode is far
      // from zero (typically 1e-2 of the largest); 1e-4 separates it from
      // the round-off level 1e-16 by twelve orders.
      CHECK(ev(6) >= 1e-4 * top);
      const Eigen::MatrixXd R = test::rigid_motions(X);
      CHECK((K * R).norm() <= 1e-12 * top * R.norm());
    }
  }

  TEST_CASE("strain_energy matches the displacement-gradient energy") {
    std::mt19937 rng(3);
    std::normal_distribution<double> g(0, 1);
    for (int trial = 0; trial < 100; ++trial) {
      const TetCorners X = random_tet(rng);
      const fem::Material mat = random_material(rng);
      Vec12 u;
      for (int i = 0; i < 12; ++i) u(i) = 1e-3 * g(rng);
      const double e1 = energy_of_assembly(X, mat, u), e2 = energy_from_gradient(X, mat, u);
      CHECK(e1 == doctest::Approx(e2).epsilon(1e-12));
      CHECK(0.5 * u.dot(fem::element_stiffness(X, mat) * u) == doctest::Approx(e2).epsilon(1e-12));
    }
  }

  TEST_CASE("K_e u is the finite-difference gradient and K_e the Hessian of strain_energy") {
    // The energy is quadratic, so central differences are exact up to round
    // off: error ~ 1e-16 |E| / h^2 with |E| ~ |K| |u|^2 and h ~ |u|, i.e.
    // ~1e-13 relative to |K|; the tolerances leave three orders of margin.
    std::mt19937 rng(5);
    std::normal_distribution<double> g(0, 1);
    for (int trial = 0; trial < 20; ++trial) {
      const TetCorners X = random_tet(rng);
      const fem::Material mat = random_material(rng);
      const double L = (X.row(1) - X.row(0)).norm();
      const double h = 1e-3 * L;
      Vec12 u;
      for (int i = 0; i < 12; ++i) u(i) = 1e-3 * L * g(rng);
      const Mat12 K = fem::element_stiffness(X, mat);
      const Vec12 grad = K * u;
      auto E = [&](const Vec12& v) { return energy_of_assembly(X, mat, v); };
      Vec12 fd_grad;
      Mat12 fd_hess;
      for (int i = 0; i < 12; ++i) {
        const Vec12 ei = h * Vec12::Unit(i);
        fd_grad(i) = (E(u + ei) - E(u - ei)) / (2 * h);
        for (int j = 0; j < 12; ++j) {
          const Vec12 ej = h * Vec12::Unit(j);
          fd_hess(i, j) = (E(u + ei + ej) - E(u + ei - ej) - E(u - ei + ej) + E(u - ei - ej)) / (4 * h * h);
        }
      }
      CHECK((fd_grad - grad).norm() <= 1e-9 * K.norm() * u.norm());
      CHECK((fd_hess - K).norm() <= 1e-9 * K.norm());
    }
  }

  TEST_CASE("strain_displacement reproduces a linear field's strain") {
    std::mt19937 rng(9);
    std::normal_distribution<double> g(0, 1);
    for (int trial = 0; trial < 50; ++trial) {
      const TetCorners X = random_tet(rng);
      Eigen::Matrix3d A;
      for (int i = 0; i < 9; ++i) A(i) = g(rng);
      const Eigen::Vector3d a(g(rng), g(rng), g(rng));
      Vec12 u;
      for (int k = 0; k < 4; ++k) u.segment<3>(3 * k) = a + A * X.row(k).transpose();
      const Eigen::Matrix<double, 6, 1> eps = fem::strain_displacement(X) * u;
      Eigen::Matrix<double, 6, 1> ref;
      ref << A(0, 0), A(1, 1), A(2, 2), A(1, 2) + A(2, 1), A(2, 0) + A(0, 2), A(0, 1) + A(1, 0);
      CHECK((eps - ref).norm() <= 1e-9 * A.norm());
    }
  }
}
