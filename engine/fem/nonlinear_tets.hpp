#pragma once
// The tets of a linear system whose force is not the linear one: a nonlinear
// law (fem/hyperelastic.hpp), or a corner whose displacement is prescribed
// nonzero. A system keeps its linear matrix A (the linear law on every tet,
// factored: the Newton preconditioner, solve/newton.hpp) and adds, over
// these tets, the correction
//     d(x) = sum_e ( f_e(X_e + u_e) - (K_e [u_e]_free - f0_e) )   on the unknowns,
// so that its residual is r = b - A x - d(x) with b the linear right-hand
// side (loads, initial strains' f0). u_e is the tets' corners' displacement:
// the unknowns' values, or the prescribed displacement of a fixed corner
// ([u_e]_free zeroes those). Its tangent is D = sum_e (K_T,e - K_e) on the
// unknown corners: zero for a linear tet, so such a tet (one with a moving
// fixed corner) only adds the constant -K_e [u_e]_fixed, the prescribed
// motion's load.
//
// NonlinearTets is rest data (fixed after construction, shared by runs);
// NonlinearWork holds one run's element tangents and what a frame reports.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "fem/element_stiffness.hpp"
#include "fem/hyperelastic.hpp"
#include "fem/material.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut {
class HelperThread;
}

namespace softcut::fem {

class NonlinearTets {
 public:
  NonlinearTets() = default;
  // tets: ids into m (each once); node_unknown (nnode of m): the unknown node
  // index k of each node (its DOFs 3k .. 3k + 2 of the system's vector), -1
  // for a fixed node. tet_material (m.num_tets()).
  NonlinearTets(const mesh::TetMesh& m, const std::vector<Material>& tet_material, std::vector<int> tets,
                const std::vector<int>& node_unknown);

  int size() const { return int(tets_.size()); }
  bool empty() const { return tets_.empty(); }
  const std::vector<int>& tets() const { return tets_; }  // mesh tet ids

  // Per tet (index into tets()).
  const TetRest& rest(int e) const { return rest_[size_t(e)]; }
  const Mat12& linear_stiffness(int e) const { return K0_[size_t(e)]; }  // K_e, N/m
  const Vec12& initial_force(int e) const { return f0_[size_t(e)]; }     // f0_e, N
  const std::array<int, 4>& unknown(int e) const { return unknown_[size_t(e)]; }  // corner -> unknown node or -1
  const std::array<int, 4>& node(int e) const { return node_[size_t(e)]; }        // corner -> mesh node
  const TetCorners& corners(int e) const { return X_[size_t(e)]; }                // rest positions, m
  // sum_e mu_e V_e^(2/3), N: the force a unit strain of the tets makes.
  double force_unit() const { return force_unit_; }

 private:
  std::vector<int> tets_;
  std::vector<TetRest> rest_;
  std::vector<Mat12> K0_;
  std::vector<Vec12> f0_;
  std::vector<std::array<int, 4>> unknown_, node_;
  std::vector<TetCorners> X_;
  double force_unit_ = 0;
};

// One run's evaluation state.
struct NonlinearWork {
  std::vector<Mat12> D;        // (size()) K_T,e - K_e, rows and columns of fixed corners zero
  std::vector<TetCorners> x;   // (size()) corner positions of the last evaluate(), m
  // Of measure_deformation() (at the last evaluate()'s positions): the
  // largest rotation and strain of any of these tets (fem::deformation), and
  // how many are inverted (det F <= 0).
  double max_rotation = 0, max_strain = 0;
  int inverted = 0;
  // NonlinearTets::force_unit() of the last evaluate(), N: for a Newton
  // scale that never asks for less than rounding (|r| <= 1e-16 of it).
  double force_unit = 0;
  std::vector<Vec12> scratch;  // (size()) a tet's share of evaluate's d or apply_difference's y
};

// d(x) added into `d` (the system's size, 3 x unknowns) for the unknowns'
// values x and the prescribed displacements of fixed corners (nnode x 3,
// rows of fixed nodes read; empty: zero); the element tangents formed into
// `work` when `tangent`. Returns the energy correction
// sum_e (E_e - 1/2 [u_e]_free^T K_e [u_e]_free + f0_e^T [u_e]_free), whose
// gradient is d (J).
// With a helper, the tets go in two fixed halves, the second on it: the same
// bits either way (and for apply_difference).
double evaluate(const NonlinearTets& set, const Eigen::VectorXd& x, const Eigen::MatrixX3d& prescribed,
                Eigen::VectorXd& d, NonlinearWork& work, bool tangent = true, HelperThread* helper = nullptr);
// work.max_rotation, max_strain and inverted at the positions of the last
// evaluate() (once per solve: a polar decomposition a tet, an eigensolve
// where the strain can pass the largest so far).
void measure_deformation(const NonlinearTets& set, NonlinearWork& work);
// Replaces work.D by the projected (positive semidefinite) element tangents
// at the positions of the last evaluate().
void project(const NonlinearTets& set, NonlinearWork& work);
// y += D p (work.scratch holds the tets' products).
void apply_difference(const NonlinearTets& set, NonlinearWork& work, const Eigen::VectorXd& p, Eigen::VectorXd& y,
                      HelperThread* helper = nullptr);

}  // namespace softcut::fem
