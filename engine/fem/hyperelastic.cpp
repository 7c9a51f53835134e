#include "fem/hyperelastic.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace softcut::fem {

namespace {

using Mat9 = Eigen::Matrix<double, 9, 9>;

// Row-major index of F_ab in a 9-vector: 3a + b.
constexpr int idx(int a, int b) { return 3 * a + b; }

Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d W;
  W << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return W;
}

Eigen::Matrix3d cofactor(const Eigen::Matrix3d& F) {  // det(F) F^-T, for every F
  Eigen::Matrix3d C;
  C.col(0) = F.col(1).cross(F.col(2));
  C.col(1) = F.col(2).cross(F.col(0));
  C.col(2) = F.col(0).cross(F.col(1));
  return C;
}

Eigen::Matrix3d cofactor_derivative(const Eigen::Matrix3d& F, const Eigen::Matrix3d& dF) {
  Eigen::Matrix3d dC;
  dC.col(0) = dF.col(1).cross(F.col(2)) + F.col(1).cross(dF.col(2));
  dC.col(1) = dF.col(2).cross(F.col(0)) + F.col(2).cross(dF.col(0));
  dC.col(2) = dF.col(0).cross(F.col(1)) + F.col(0).cross(dF.col(1));
  return dC;
}

// The linear law's energy density of a strain e, J/m^3.
double linear_density(const TetRest& r, const Eigen::Matrix3d& e) {
  return r.mu * e.squaredNorm() + 0.5 * r.lambda * e.trace() * e.trace();
}

// The stress measure and its derivative of one law at one F, as the kernel
// needs them: P (first Piola-Kirchhoff, Pa), its energy density W (J/m^3 of
// rest volume), and dP for a given dF through `dP(dF)` or, for the unit dF =
// e_b e_d^T, `dP_unit(b, d)`.
struct Linear {
  const TetRest& r;
  Eigen::Matrix3d e, P;
  Linear(const TetRest& rest, const Eigen::Matrix3d& F) : r(rest) {
    e = 0.5 * (F + F.transpose()) - Eigen::Matrix3d::Identity() - r.eps0;
    P = 2 * r.mu * e + r.lambda * e.trace() * Eigen::Matrix3d::Identity();
  }
  double density() const { return linear_density(r, e); }
  Eigen::Matrix3d dP(const Eigen::Matrix3d& dF) const {
    return r.mu * (dF + dF.transpose()) + r.lambda * dF.trace() * Eigen::Matrix3d::Identity();
  }
};

struct Corotational {
  const TetRest& r;
  Eigen::Matrix3d R, S, Minv, e, sig, P, RA;
  Corotational(const TetRest& rest, const Eigen::Matrix3d& F) : r(rest) {
    polar(F, R, S, &Minv);
    e = S - Eigen::Matrix3d::Identity() - r.eps0;
    sig = 2 * r.mu * e + r.lambda * e.trace() * Eigen::Matrix3d::Identity();
    P = R * sig;
    RA = R * (sig - 2 * r.mu * S);
  }
  double density() const { return linear_density(r, e); }
  // With B = R^T dF, W = R^T dR = skew(Minv axial(B)) and dS = B - W S:
  //   dP = R (W sig + 2 mu dS + lambda tr(dS) I)
  //      = skew(R w) RA + 2 mu dF + lambda tr(B) R,   w = Minv axial(B),
  // RA = R (sig - 2 mu S) (R skew(w) = skew(R w) R; tr(W S) = 0). For the
  // unit dF = e_b e_d^T the tangent is made of, B = (R^T e_b) e_d^T:
  // axial(B) = e_d x R^T e_b and tr(B) = R(b, d).
  Eigen::Matrix3d dP_unit(int b, int d) const {
    const Eigen::Vector3d w = Minv * Eigen::Vector3d::Unit(d).cross(R.row(b).transpose());
    Eigen::Matrix3d out = skew(R * w) * RA + r.lambda * R(b, d) * R;
    out(b, d) += 2 * r.mu;
    return out;
  }
  // The exact tangent straight from dP's three terms, without the 9 x 9 H
  // (a third of the flops: an element with its tangent 1.09 -> 0.74 us).
  // With H(ac, bd) = dP_ac / dF_bd and K(3k+a, 3l+b) = V sum_cd H(ac, bd)
  // g_k[c] g_l[d] (g_k: row k of grad):
  //   2 mu dF          -> 2 mu V (g_k . g_l) delta_ab
  //   lambda tr(B) R   -> lambda V (R g_k)_a (R g_l)_b
  //   skew(R w) RA     -> V sum_m (A_m g_k)_a (g_l x r_b)_m,
  // A_m = skew(R Minv e_m) RA, r_b = row b of R (w = Minv (e_d x r_b) is
  // linear in e_d). Symmetrised as the H path is (exactly equal in exact
  // arithmetic; the finite-difference tangent test holds it to 1e-6).
  void tangent(Mat12& K) const {
    const Eigen::Matrix<double, 4, 3>& g = r.grad;
    const Eigen::Matrix3d RM = R * Minv;
    Eigen::Matrix3d A[3];
    for (int m = 0; m < 3; ++m) A[m] = skew(RM.col(m)) * RA;
    Eigen::Matrix3d U[4], W[4];  // U_k(a, m) = (A_m g_k)_a; W_l(b, m) = (g_l x r_b)_m
    Eigen::Matrix<double, 3, 4> Rg = R * g.transpose();
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d gk = g.row(k).transpose();
      for (int m = 0; m < 3; ++m) U[k].col(m) = A[m] * gk;
      for (int b = 0; b < 3; ++b) W[k].row(b) = gk.cross(R.row(b).transpose()).transpose();
    }
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < 4; ++l) {
        Eigen::Matrix3d B = U[k] * W[l].transpose() + r.lambda * Rg.col(k) * Rg.col(l).transpose();
        B.diagonal().array() += 2 * r.mu * g.row(k).dot(g.row(l));
        K.block<3, 3>(3 * k, 3 * l) = r.volume * B;
      }
    K = (0.5 * (K + K.transpose())).eval();
  }
};

// J below kJ0 enters the isochoric term as J0 exp((J - J0) / J0): positive,
// C1 at J0, so an inverted tet has a finite energy, force and tangent.
constexpr double kJ0 = 0.2;

struct NeoHookean {
  const TetRest& r;
  Eigen::Matrix3d G, F, C, P;  // F here is F F0^-1
  double c10, k2, J, I1, a1, a2;  // a1 = da/dJ, a2 = d2a/dJ2 of a(J) = Jhat(J)^-2/3
  double a;
  NeoHookean(const TetRest& rest, const Eigen::Matrix3d& F_total) : r(rest) {
    G = (Eigen::Matrix3d::Identity() + r.eps0).inverse();
    F = F_total * G;
    c10 = 0.5 * r.mu;
    k2 = r.lambda + 2.0 / 3.0 * r.mu;  // 2 / D1 = K
    C = cofactor(F);
    J = F.determinant();
    I1 = F.squaredNorm();
    double jh = J, d1 = 1, d2 = 0;
    if (J < kJ0) {
      jh = kJ0 * std::exp((J - kJ0) / kJ0);
      d1 = jh / kJ0;
      d2 = jh / (kJ0 * kJ0);
    }
    a = std::pow(jh, -2.0 / 3.0);
    a1 = -2.0 / 3.0 * a / jh * d1;
    a2 = 10.0 / 9.0 * a / (jh * jh) * d1 * d1 - 2.0 / 3.0 * a / jh * d2;
    // Isochoric part 2 c10 a (F - I1/3 F^-T) where Jhat = J: exactly zero at
    // F = I (the general form c10 (2 a F + I1 a1 C) leaves a rounding residue).
    const Eigen::Matrix3d iso = J >= kJ0 ? Eigen::Matrix3d(2 * c10 * a * (F - I1 / 3 * C / J))
                                         : Eigen::Matrix3d(c10 * (2 * a * F + I1 * a1 * C));
    P = (iso + k2 * (J - 1) * C) * G.transpose();
  }
  double density() const { return c10 * (a * I1 - 3) + 0.5 * k2 * (J - 1) * (J - 1); }
  Eigen::Matrix3d dP(const Eigen::Matrix3d& dF_total) const {
    const Eigen::Matrix3d dF = dF_total * G;
    const double dJ = (C.array() * dF.array()).sum();
    const double dI1 = 2 * (F.array() * dF.array()).sum();
    const Eigen::Matrix3d dC = cofactor_derivative(F, dF);
    const Eigen::Matrix3d dPe = c10 * (2 * a1 * dJ * F + 2 * a * dF + (dI1 * a1 + I1 * a2 * dJ) * C + I1 * a1 * dC) +
                                k2 * (dJ * C + (J - 1) * dC);
    return dPe * G.transpose();
  }
};

// dP for dF = e_b e_d^T: the law's own shortcut where it has one.
template <class Law>
Eigen::Matrix3d unit_derivative(const Law& law, int b, int d) {
  if constexpr (requires { law.dP_unit(b, d); }) {
    return law.dP_unit(b, d);
  } else {
    Eigen::Matrix3d dF = Eigen::Matrix3d::Zero();
    dF(b, d) = 1;
    return law.dP(dF);
  }
}

// f and K from P and dP: f_k = V P g_k; K(3k + a, 3l + b) = V sum_cd H(ac, bd) g_k[c] g_l[d].
template <class Law>
void assemble(const TetRest& r, const Law& law, Vec12& f, Mat12* K, Tangent tangent, double* energy) {
  for (int k = 0; k < 4; ++k) f.segment<3>(3 * k) = r.volume * (law.P * r.grad.row(k).transpose());
  if (energy) *energy = r.volume * law.density();
  if (!K || tangent == Tangent::none) return;
  if constexpr (requires(Mat12& out) { law.tangent(out); })
    if (tangent == Tangent::exact) return law.tangent(*K);
  Mat9 H;  // H(idx(a, c), idx(b, d)) = dP_ac / dF_bd
  for (int b = 0; b < 3; ++b)
    for (int d = 0; d < 3; ++d) {
      const Eigen::Matrix3d dP = unit_derivative(law, b, d);
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) H(idx(a, c), idx(b, d)) = dP(a, c);
    }
  H = (0.5 * (H + H.transpose())).eval();
  if (tangent == Tangent::projected) {
    const Eigen::SelfAdjointEigenSolver<Mat9> eig(H);
    const Eigen::Matrix<double, 9, 1> lam = eig.eigenvalues().cwiseMax(0.0);
    H = eig.eigenvectors() * lam.asDiagonal() * eig.eigenvectors().transpose();
  }
  const Eigen::Matrix<double, 4, 3>& g = r.grad;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      Eigen::Matrix3d Hab;
      for (int c = 0; c < 3; ++c)
        for (int d = 0; d < 3; ++d) Hab(c, d) = H(idx(a, c), idx(b, d));
      const Eigen::Matrix4d Kab = r.volume * (g * Hab * g.transpose());
      for (int k = 0; k < 4; ++k)
        for (int l = 0; l < 4; ++l) (*K)(3 * k + a, 3 * l + b) = Kab(k, l);
    }
  *K = (0.5 * (*K + K->transpose())).eval();
}

}  // namespace

void polar(const Eigen::Matrix3d& F, Eigen::Matrix3d& R, Eigen::Matrix3d& S, Eigen::Matrix3d* Minv) {
  // A tet well away from flat (det F > 0 and not small against |F|^3):
  // Higham's scaled Newton iteration R <- (g R + (g R)^-T) / 2, which keeps
  // S - I to about 3e-16 absolute (10x closer than through the SVD, whose
  // singular vectors blur where the stretches are equal: the strain of a
  // nearly rigid tet, which a converged Newton frame's residual is made of).
  const double fn = F.norm() / std::sqrt(3.0);
  const double det = F.determinant();
  if (std::isfinite(det) && det > 1e-2 * fn * fn * fn) {
    R = F;
    for (int k = 0; k < 30; ++k) {
      // (g R)^-T = cof(R) / (g det R), g = |det R|^(-1/3): one determinant
      // and one cofactor a step (no general inverse, no pow). The scaling
      // only speeds the first steps: g = 1 once det R is within 1e-3 of 1
      // (the plain Newton step, as quadratic there; the cube root was a
      // quarter of the polar's time).
      const double dr = R.determinant(), g = std::abs(dr - 1) > 1e-3 ? 1.0 / std::cbrt(std::abs(dr)) : 1.0;
      const Eigen::Matrix3d next = 0.5 * (g * R + cofactor(R) / (g * dr));
      const double change = (next - R).lpNorm<Eigen::Infinity>();
      R = next;
      if (change <= 1e-15) break;
    }
    S = 0.5 * (R.transpose() * F + F.transpose() * R);
    if (Minv) *Minv = (S.trace() * Eigen::Matrix3d::Identity() - S).inverse();
    return;
  }
  // Flat or inverted: through the SVD F = U Sigma V^T, both reflections (if
  // any) on the smallest singular value, so that R = U V^T stays a rotation
  // and S = V Sigma V^T takes the sign.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
  Eigen::Vector3d s = svd.singularValues();
  if (U.determinant() < 0) U.col(2) *= -1, s(2) *= -1;
  if (V.determinant() < 0) V.col(2) *= -1, s(2) *= -1;
  R = U * V.transpose();
  S = V * s.asDiagonal() * V.transpose();
  if (!Minv) return;
  // (tr S I - S)^-1: eigenvalues 1 / (sigma_j + sigma_k), which vanish only
  // for a tet flattened or inverted across two axes; bounded there so that
  // the tangent stays finite (the force does not use it).
  const double floor = 1e-6 * std::max(1.0, s.cwiseAbs().maxCoeff());
  Eigen::Vector3d d(s(1) + s(2), s(0) + s(2), s(0) + s(1));
  for (int k = 0; k < 3; ++k) d(k) = 1.0 / std::max(d(k), floor);
  *Minv = V * d.asDiagonal() * V.transpose();
}

TetRest tet_rest(const TetCorners& X, const Material& mat) {
  Eigen::Matrix3d Dm;
  for (int k = 0; k < 3; ++k) Dm.col(k) = (X.row(k + 1) - X.row(0)).transpose();
  TetRest r;
  r.volume = Dm.determinant() / 6.0;
  r.Dm_inv = Dm.inverse();
  r.grad.bottomRows<3>() = r.Dm_inv;
  r.grad.row(0) = -r.Dm_inv.colwise().sum();
  const double E = mat.young, nu = mat.poisson;
  r.lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  r.mu = E / (2 * (1 + nu));
  const auto& e = mat.initial_strain;  // Voigt, engineering shears
  r.eps0 << e[0], 0.5 * e[5], 0.5 * e[4], 0.5 * e[5], e[1], 0.5 * e[3], 0.5 * e[4], 0.5 * e[3], e[2];
  r.model = mat.model;
  return r;
}

Eigen::Matrix3d deformation_gradient(const TetRest& r, const TetCorners& x) {
  return x.transpose() * r.grad;  // sum_k x_k g_k^T
}

void element_force(const TetRest& r, const TetCorners& x, Vec12& f, Mat12* K, Tangent tangent, double* energy) {
  const Eigen::Matrix3d F = deformation_gradient(r, x);
  switch (r.model) {
    case MaterialModel::linear: assemble(r, Linear(r, F), f, K, tangent, energy); break;
    case MaterialModel::corotational: assemble(r, Corotational(r, F), f, K, tangent, energy); break;
    case MaterialModel::neohookean: assemble(r, NeoHookean(r, F), f, K, tangent, energy); break;
  }
}

double element_energy(const TetRest& r, const TetCorners& x) {
  Vec12 f;
  double energy = 0;
  element_force(r, x, f, nullptr, Tangent::none, &energy);
  return energy;
}

Deformation deformation(const Eigen::Matrix3d& F, double strain_floor) {
  Eigen::Matrix3d R, S;
  polar(F, R, S);
  Deformation d;
  d.rotation = std::acos(std::clamp(0.5 * (R.trace() - 1), -1.0, 1.0));
  // max |sigma_k - 1| <= |S - I|_F: no eigensolve where that cannot pass the floor.
  if ((S - Eigen::Matrix3d::Identity()).norm() <= strain_floor) return d;
  const Eigen::Vector3d s = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(S, Eigen::EigenvaluesOnly).eigenvalues();
  d.strain = (s.array() - 1).abs().maxCoeff();
  return d;
}

}  // namespace softcut::fem
