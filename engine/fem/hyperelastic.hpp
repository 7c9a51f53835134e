#pragma once
// Large-deformation element kernels of a linear tetrahedron (DESIGN.md §1b):
// the internal force f = dE/dx (N) of one tet at current corner positions,
// its exact tangent df/dx (N/m), and what a frame reports of the tet (its
// rotation and strain), for every MaterialModel:
//   linear        P = sigma(eps),  eps = sym(F) - I - eps0 (f = K_e u - f0)
//   corotational  F = R S (polar, R a rotation even for a flattened or
//                 inverted tet), P = R sigma'(S - I - eps0): linear
//                 elasticity in the tet's rotated frame; f = R (K_e (R^T x - X) - f0)
//   neohookean    CalculiX's NEO HOOKE, W = C10 (J^-2/3 I1 - 3) + (J - 1)^2 / D1,
//                 C10 = mu / 2, D1 = 2 / K, on F F0^-1 with F0 = I + eps0
// F = Ds Dm^-1 is the deformation gradient (Ds, Dm: current and rest edge
// matrices), sigma the linear stress (Lame mu, lambda). The tangent includes
// the rotation's derivative (the corotational force is the gradient of the
// corotated energy mu |S - I|^2 + lambda/2 tr(S - I)^2 when eps0 = 0, so its
// tangent is then symmetric; with eps0 it is symmetrised). Nothing is NaN for
// any finite x: a flat or inverted tet gets a finite force and tangent.
#include <Eigen/Core>

#include "fem/element_stiffness.hpp"
#include "fem/material.hpp"

namespace softcut::fem {

using Vec12 = Eigen::Matrix<double, 12, 1>;

// What a tet keeps of its rest shape and material (per tet, fixed).
struct TetRest {
  Eigen::Matrix3d Dm_inv;                 // inverse rest edge matrix, 1/m
  Eigen::Matrix<double, 4, 3> grad;       // row k: rest gradient of corner k's shape function, 1/m
  double volume = 0;                      // rest volume, m^3
  double mu = 0, lambda = 0;              // Lame parameters, Pa
  Eigen::Matrix3d eps0 = Eigen::Matrix3d::Zero();  // initial strain tensor (rest frame)
  MaterialModel model = MaterialModel::linear;
};

// X: rest corners (positively oriented; the assembler checks).
TetRest tet_rest(const TetCorners& X, const Material& mat);

// How the tangent is made.
enum class Tangent {
  none,       // force only
  exact,      // df/dx, symmetrised
  projected,  // the exact tangent with its negative eigenvalues (in F-space) set to 0: positive semidefinite
};

// Internal force f (12: corners' x y z, N) of the tet at current corner
// positions x (4 x 3, m), and its tangent K (12 x 12, N/m) unless
// Tangent::none, and its energy (element_energy) into `energy` unless null:
// one pass of the law (one polar decomposition) for all three. f = 0 at
// x = rest for eps0 = 0; rigid motions give f = 0.
void element_force(const TetRest& r, const TetCorners& x, Vec12& f, Mat12* K = nullptr,
                   Tangent tangent = Tangent::none, double* energy = nullptr);

// The tet's stored energy at x, J: the potential whose gradient is
// element_force (for every law but the corotational one with an initial
// strain, whose rotated prestress is not conservative; the tangent is then
// the symmetric part of df/dx). For checks.
double element_energy(const TetRest& r, const TetCorners& x);

// The deformation gradient of the tet at x.
Eigen::Matrix3d deformation_gradient(const TetRest& r, const TetCorners& x);

// What a frame reports of a tet (DESIGN.md §1b: when a model is out of its depth).
struct Deformation {
  double rotation = 0;  // angle of the polar rotation of F, rad (0 .. pi)
  double strain = 0;    // largest principal stretch's distance from 1, |sigma_k - 1| (a flipped tet: > 1)
};
// strain_floor: where the strain cannot pass it (|S - I|_F <= floor), it is
// not computed and reported as 0 (a caller after the largest over many
// tets passes the largest so far: the eigensolve is most of the cost).
Deformation deformation(const Eigen::Matrix3d& F, double strain_floor = -1);

// Polar decomposition F = R S with R a rotation (det +1) for every F: a tet
// well away from flat by Higham's scaled Newton iteration, a flat or
// inverted one through the SVD with the reflection put on the smallest
// singular value (S then has one negative eigenvalue). Minv (optional):
// (tr S I - S)^-1, the rotation's derivative's kernel, bounded for a tet
// flattened across two axes.
void polar(const Eigen::Matrix3d& F, Eigen::Matrix3d& R, Eigen::Matrix3d& S, Eigen::Matrix3d* Minv = nullptr);

}  // namespace softcut::fem
