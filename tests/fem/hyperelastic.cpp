// fem/hyperelastic: the large-deformation element kernels against what must
// hold of them whatever the implementation: the force is the energy's
// gradient (central differences), the tangent the force's derivative, rigid
// motions give no force, a rotated problem gives the rotated answer, small
// motions give the linear element (K_e u - f0), and a flattened or inverted
// tet gives finite numbers.
#include "fem/hyperelastic.hpp"

#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>

#include "fem/assembly.hpp"

using namespace softcut;
using fem::MaterialModel;

namespace {

const MaterialModel kLaws[] = {MaterialModel::linear, MaterialModel::corotational, MaterialModel::neohookean};

fem::TetCorners random_tet(std::mt19937& rng) {
  std::uniform_real_distribution<double> d(-0.3, 0.3);
  fem::TetCorners X;
  X << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  for (int i = 0; i < 12; ++i) X(i) += d(rng);
  if (fem::tet_rest(X, {}).volume < 0) X.row(1).swap(X.row(2));
  return 0.01 * X;  // a 1 cm tet
}

Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> g(0, 1);
  return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}

fem::Material material(MaterialModel m, bool prestress) {
  fem::Material mat{4e3, 0.42};
  mat.model = m;
  if (prestress) mat.initial_strain = {-0.03, 0.02, 0.01, 0.004, -0.006, 0.01};
  return mat;
}

Eigen::Map<const fem::Vec12> flat(const fem::TetCorners& x) {
  static thread_local fem::Vec12 v;
  for (int k = 0; k < 4; ++k) v.segment<3>(3 * k) = x.row(k).transpose();
  return Eigen::Map<const fem::Vec12>(v.data());
}

fem::TetCorners corners(const fem::Vec12& v) {
  fem::TetCorners x;
  for (int k = 0; k < 4; ++k) x.row(k) = v.segment<3>(3 * k).transpose();
  return x;
}

fem::Vec12 force(const fem::TetRest& r, const fem::Vec12& x) {
  fem::Vec12 f;
  fem::element_force(r, corners(x), f);
  return f;
}

}  // namespace

TEST_SUITE("fem/hyperelastic") {
  TEST_CASE("the force is the gradient of the energy, and the tangent the derivative of the force") {
    std::mt19937 rng(3);
    std::normal_distribution<double> g(0, 1);
    for (int trial = 0; trial < 40; ++trial)
      for (MaterialModel law : kLaws)
        for (bool prestress : {false, true}) {
          const fem::TetCorners X = random_tet(rng);
          const fem::TetRest r = fem::tet_rest(X, material(law, prestress));
          // A large motion: a rotation, a stretch of up to 40 % and a shear.
          Eigen::Matrix3d A = random_rotation(rng);
          for (int i = 0; i < 9; ++i) A(i) += 0.2 * g(rng);
          fem::Vec12 x;
          for (int k = 0; k < 4; ++k) x.segment<3>(3 * k) = A * X.row(k).transpose() + Eigen::Vector3d(0.01, 0, 0);
          fem::Vec12 f;
          fem::Mat12 K;
          fem::element_force(r, corners(x), f, &K, fem::Tangent::exact);
          CAPTURE(trial);
          CAPTURE(fem::to_string(law));
          CAPTURE(prestress);
          const double h = 1e-7 * 0.01;
          fem::Mat12 Kfd;
          fem::Vec12 grad;
          for (int i = 0; i < 12; ++i) {
            fem::Vec12 xp = x, xm = x;
            xp(i) += h, xm(i) -= h;
            Kfd.col(i) = (force(r, xp) - force(r, xm)) / (2 * h);
            grad(i) = (fem::element_energy(r, corners(xp)) - fem::element_energy(r, corners(xm))) / (2 * h);
          }
          const bool conservative = !(law == MaterialModel::corotational && prestress);
          if (conservative) {
            CHECK((grad - f).norm() <= 1e-6 * f.norm());
            CHECK((Kfd - K).norm() <= 1e-6 * K.norm());
          } else {  // the rotated prestress: the tangent is df/dx's symmetric part
            CHECK((0.5 * (Kfd + Kfd.transpose()) - K).norm() <= 1e-6 * K.norm());
            CHECK((Kfd - Kfd.transpose()).norm() > 1e-9 * K.norm());  // which is not symmetric
          }
          CHECK((K - K.transpose()).norm() == 0);
        }
  }

  TEST_CASE("the linear law is the linear element: f = K_e u - f0, tangent K_e") {
    std::mt19937 rng(5);
    std::normal_distribution<double> g(0, 1);
    for (int trial = 0; trial < 10; ++trial) {
      const fem::TetCorners X = random_tet(rng);
      const fem::Material mat = material(MaterialModel::linear, true);
      const fem::TetRest r = fem::tet_rest(X, mat);
      fem::Vec12 u;
      for (int i = 0; i < 12; ++i) u(i) = 1e-3 * g(rng);
      fem::Vec12 f;
      fem::Mat12 K;
      fem::element_force(r, corners(flat(X) + u), f, &K, fem::Tangent::exact);
      const fem::Mat12 Ke = fem::element_stiffness(X, mat);
      mesh::TetMesh one;
      one.nodes = X;
      one.tets.resize(1, 4);
      one.tets << 0, 1, 2, 3;
      one.labels = Eigen::VectorXi::Zero(1);
      const Eigen::MatrixX3d f0 = fem::element_loads(one, {mat});
      fem::Vec12 f0v;
      for (int k = 0; k < 4; ++k) f0v.segment<3>(3 * k) = f0.row(k).transpose();
      CHECK((f - (Ke * u - f0v)).norm() <= 1e-10 * (Ke * u).norm());
      CHECK((K - Ke).norm() <= 1e-12 * Ke.norm());
    }
  }

  TEST_CASE("rigid motions give no force (corotational, neo-Hookean) and rotating the tet rotates force and tangent") {
    std::mt19937 rng(7);
    std::normal_distribution<double> g(0, 1);
    for (int trial = 0; trial < 20; ++trial) {
      const fem::TetCorners X = random_tet(rng);
      const Eigen::Matrix3d Q = random_rotation(rng);
      const Eigen::Vector3d t(g(rng), g(rng), g(rng));
      for (MaterialModel law : {MaterialModel::corotational, MaterialModel::neohookean}) {
        CAPTURE(fem::to_string(law));
        const fem::TetRest r = fem::tet_rest(X, material(law, false));
        fem::TetCorners moved = (X * Q.transpose()).rowwise() + t.transpose();
        fem::Vec12 f;
        fem::element_force(r, moved, f);
        CHECK(f.norm() <= 1e-9 * r.mu * std::cbrt(r.volume) * std::cbrt(r.volume));
        // Some deformation, then the same deformation rotated.
        fem::TetCorners x = X;
        for (int i = 0; i < 12; ++i) x(i) += 0.002 * g(rng);
        fem::Vec12 f1, f2;
        fem::Mat12 K1, K2;
        fem::element_force(r, x, f1, &K1, fem::Tangent::exact);
        fem::element_force(r, (x * Q.transpose()).rowwise() + t.transpose(), f2, &K2, fem::Tangent::exact);
        fem::Mat12 Qb = fem::Mat12::Zero();
        for (int k = 0; k < 4; ++k) Qb.block<3, 3>(3 * k, 3 * k) = Q;
        CHECK((f2 - Qb * f1).norm() <= 1e-9 * f1.norm());
        CHECK((K2 - Qb * K1 * Qb.transpose()).norm() <= 1e-9 * K1.norm());
      }
      // The linear law is not rotation invariant: a rigid rotation strains it.
      const fem::TetRest lin = fem::tet_rest(X, material(MaterialModel::linear, false));
      fem::Vec12 f;
      fem::element_force(lin, (X * Q.transpose()).rowwise() + t.transpose(), f);
      CHECK(f.norm() > 1e-3 * lin.mu * std::cbrt(lin.volume) * std::cbrt(lin.volume));
    }
  }

  TEST_CASE("small motions reproduce the linear element: the difference shrinks with the strain") {
    std::mt19937 rng(9);
    std::normal_distribution<double> g(0, 1);
    const fem::TetCorners X = random_tet(rng);
    fem::Vec12 u;  // a motion of unit strain scale: |u| ~ the tet's size
    for (int i = 0; i < 12; ++i) u(i) = 0.01 * g(rng);
    const fem::TetRest lin = fem::tet_rest(X, material(MaterialModel::linear, false));
    for (MaterialModel law : {MaterialModel::corotational, MaterialModel::neohookean}) {
      CAPTURE(fem::to_string(law));
      const fem::TetRest r = fem::tet_rest(X, material(law, false));
      for (double s : {1e-3, 1e-5, 1e-7}) {
        fem::Vec12 a, b;
        fem::element_force(lin, corners(flat(X) + s * u), a);
        fem::element_force(r, corners(flat(X) + s * u), b);
        CAPTURE(s);
        CHECK((a - b).norm() <= 10 * s * a.norm());  // second order: the difference / the force ~ the strain
      }
    }
  }

  TEST_CASE("flattened, inverted and collapsed tets give finite forces and tangents, never NaN") {
    std::mt19937 rng(11);
    const fem::TetCorners X = random_tet(rng);
    fem::TetCorners flat_tet = X, inverted = X, point = X;
    flat_tet.col(2).setConstant(X(0, 2));   // all four corners in one plane
    inverted.row(3) = X.row(0) - (X.row(3) - X.row(0));  // corner 3 pushed through the opposite face
    point.rowwise() = X.row(0);             // collapsed to a point
    for (MaterialModel law : kLaws)
      for (const fem::TetCorners* x : {&flat_tet, &inverted, &point}) {
        CAPTURE(fem::to_string(law));
        const fem::TetRest r = fem::tet_rest(X, material(law, true));
        fem::Vec12 f;
        fem::Mat12 K;
        for (fem::Tangent t : {fem::Tangent::exact, fem::Tangent::projected}) {
          fem::element_force(r, *x, f, &K, t);
          CHECK(f.allFinite());
          CHECK(K.allFinite());
        }
        CHECK(std::isfinite(fem::element_energy(r, *x)));
        // An inverted corotational tet is pushed back: the force on corner 3
        // (= -dE/dx3 on the tissue) points back through the face.
        if (law == MaterialModel::corotational && x == &inverted) {
          fem::element_force(r, *x, f);
          CHECK(-f.segment<3>(9).dot((X.row(3) - X.row(0)).transpose()) > 0);
        }
      }
  }

  TEST_CASE("the projected tangent is positive semidefinite and equals the exact one where that is") {
    std::mt19937 rng(13);
    std::normal_distribution<double> g(0, 1);
    int indefinite = 0;
    for (int trial = 0; trial < 40; ++trial) {
      const fem::TetCorners X = random_tet(rng);
      const fem::TetRest r = fem::tet_rest(X, material(MaterialModel::corotational, false));
      Eigen::Matrix3d A = random_rotation(rng) * (0.5 + 0.1 * trial / 4.0);  // compressed up to stretched
      fem::TetCorners x = X * A.transpose();
      fem::Vec12 f;
      fem::Mat12 Ke, Kp;
      fem::element_force(r, x, f, &Ke, fem::Tangent::exact);
      fem::element_force(r, x, f, &Kp, fem::Tangent::projected);
      const Eigen::SelfAdjointEigenSolver<fem::Mat12> ee(Ke), ep(Kp);
      CHECK(ep.eigenvalues().minCoeff() >= -1e-9 * ep.eigenvalues().maxCoeff());
      if (ee.eigenvalues().minCoeff() < -1e-9 * ee.eigenvalues().maxCoeff()) ++indefinite;
      else CHECK((Ke - Kp).norm() <= 1e-9 * Ke.norm());
    }
    CHECK(indefinite > 0);  // compression past the twist modes' stability: the exact tangent is indefinite
  }

  TEST_CASE("polar: R is a rotation and R S = F, also for an inverted F, and deformation reports angle and stretch") {
    std::mt19937 rng(17);
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::Matrix3d Q = random_rotation(rng);
      const Eigen::Matrix3d F = Q * Eigen::Vector3d(1.3, 0.9, trial % 2 ? -0.5 : 0.7).asDiagonal();
      Eigen::Matrix3d R, S;
      fem::polar(F, R, S);
      CHECK(R.determinant() == doctest::Approx(1.0));
      CHECK((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() <= 1e-12);
      CHECK((R * S - F).norm() <= 1e-12);
      CHECK((S - S.transpose()).norm() <= 1e-12);
      CHECK((R - Q).norm() <= 1e-12);
      const fem::Deformation d = fem::deformation(F);
      CHECK(d.rotation == doctest::Approx(Eigen::AngleAxisd(Q).angle()).epsilon(1e-9));
      CHECK(d.strain == doctest::Approx(trial % 2 ? 1.5 : 0.3));
      // Below a floor the strain cannot pass (|S - I|_F <= floor) it is not computed.
      const double bound = (S - Eigen::Matrix3d::Identity()).norm();
      const fem::Deformation above = fem::deformation(F, 0.99 * d.strain), below = fem::deformation(F, bound);
      CHECK(above.strain == d.strain);
      CHECK(above.rotation == d.rotation);
      CHECK(below.strain == 0);
      CHECK(below.rotation == d.rotation);
      CHECK(bound >= d.strain);
    }
  }

  // A converged frame's residual is made of the strains of nearly rigid
  // tets: S - I must keep its digits when the strain is far below 1.
  TEST_CASE("polar keeps the strain of a nearly rigid tet to about 1e-15 absolute") {
    std::mt19937 rng(19);
    std::normal_distribution<double> g(0, 1);
    for (double strain : {1e-2, 1e-4, 1e-6}) {
      double worst = 0;
      for (int trial = 0; trial < 50; ++trial) {
        Eigen::Matrix3d E;  // a symmetric strain
        for (int i = 0; i < 9; ++i) E(i) = strain * g(rng);
        E = (0.5 * (E + E.transpose())).eval();
        const Eigen::Matrix3d Q = random_rotation(rng);
        Eigen::Matrix3d R, S;
        fem::polar(Q * (Eigen::Matrix3d::Identity() + E), R, S);
        worst = std::max(worst, (S - Eigen::Matrix3d::Identity() - E).norm());
      }
      CAPTURE(strain);
      CHECK(worst <= 2e-15);
    }
  }
}
