#pragma once
// A cut operational system solved exactly with the CHOLMOD factor of an
// earlier system of the same run (issue #14: after a cut, do not throw the
// factor away).
//
// A cut changes the system N = K + K' only in the node rows its tets touch,
// and appends nodes (it may also drop some); K' never changes. The factor of
// the base system M (P M P' = L L') still describes every other row.
//
// Appended nodes (a) are eliminated first: with x = [x_o; x_a] (x_o on the
// base's DOFs; a dropped node keeps its row of M there, decoupled),
//
//   x_a = N_aa^-1 (b_a - N_ao x_o),   R x_o = b_o - N_oa N_aa^-1 b_a,
//   R = N_oo - N_oa N_aa^-1 N_ao = M + E Delta E'
//
// where E selects the k base DOFs whose rows changed (the appended nodes'
// neighbours among them) and Delta (k x k, dense) is R - M on them. N_aa is
// small and sparse (its own CHOLMOD factor); only the changed DOFs J that
// touch an appended node enter the Schur term N_oa (N_aa^-1 N_aJ). R is
// solved with M's factor by Sherman-Morrison-Woodbury:
//
//   y = L^-1 P c,   (I + G Delta) z = W' y,   x_o = P' L'^-1 (y - W Delta z)
//
// with W = L^-1 P E (n x k, one forward solve per changed DOF) and
// G = W'W = E' M^-1 E. No inverse of Delta is needed (it is singular when a
// cut only removes stiffness). Columns of W are kept while the base is, so a
// second cut against the same base solves only for its newly changed DOFs.
//
// Cost: c new columns cost c forward solves along their elimination-tree
// paths (at most 2 nnz(L) flops each, what the budget counts; BLAS 3) and
// a Gram update (2 n c cols), plus about 5 k^3 for the capacitance matrix
// and the check that N is positive definite; a frame costs one solve with
// the base factor, two n x k products, a k x k LU solve and two small sparse
// solves for the appended nodes. The caller weighs that against a refactor
// (Cholesky::factor_flops) and checks every residual.
#include <Eigen/Core>
#include <Eigen/LU>
#include <vector>

#include "core/helper_thread.hpp"
#include "hybrid/operational_system.hpp"
#include "solve/cholesky.hpp"

namespace softcut::hybrid {

class FactorCorrection {
 public:
  // New columns (forward solves and Gram entries), the appended nodes' Schur
  // solves, G Delta and G Delta G, a solve's two n x k products and the
  // products beside its triangular solves' dense top block run in two fixed
  // halves, the second on `helper` when it is awake (OpenBLAS on
  // one thread meanwhile, so the two do not fight over its pool): the same
  // bits with or without it. Null: both halves on the caller.
  void share_helper(HelperThread* helper) { helper_ = helper; }

  // Forgets every kept column (a new base).
  void clear();

  // Prepares solves of `next` with `base` and its factor F. False when the
  // systems differ in their interface or K', when either lacks its
  // node-block rows, when more than `max_dofs` DOFs changed, when the new
  // columns would cost more than `max_flops`, or when `next` is not clearly
  // positive definite (then a refactor says why); the prepared system is
  // then none. *flops gets the cost of the columns and Gram entries computed.
  // Kept columns belong to one base (its generation).
  bool prepare(const OperationalSystem& base, const solve::Cholesky& F, const OperationalSystem& next, int max_dofs,
               double max_flops, solve::SolveWorkspace& ws, double* flops = nullptr);

  // x = next^-1 b (`next` as last prepared; b and x in its DOF order).
  void solve(const solve::Cholesky& F, const Eigen::VectorXd& b, Eigen::VectorXd& x, solve::SolveWorkspace& ws);

  int rank() const { return int(changed_.size()); }  // k: changed DOFs of the prepared system
  int kept_columns() const { return cols_; }
  double kept_bytes() const { return 8.0 * double(W_.size() + gram_.size()); }

 private:
  template <class Work>
  void column_halves(Eigen::Index n, const Work& work);

  HelperThread* helper_ = nullptr;
  solve::SolveWorkspace helper_ws_;  // CHOLMOD's workspace for the helper's half
  int base_dofs_ = 0;                // n: DOFs of the base system (rows of W)
  long base_generation_ = -1;        // the base the kept columns belong to
  // Columns kept for this base: W(:, c) = L^-1 P e_{dof_of_col_[c]}, in
  // the first cols_ columns of storage that grows by doubling (a cut adds
  // tens of columns to hundreds: no copy of all of them per cut).
  int cols_ = 0;
  Eigen::MatrixXd W_;                // (n x capacity)
  Eigen::MatrixXd gram_;             // (capacity x capacity) W'W on the first cols_
  std::vector<int> col_of_dof_;      // (n) column of each base DOF, -1 if none

  // The prepared system.
  std::vector<int> ext_of_next_;     // (next.size()) base DOF (< n) or n + appended DOF of each DOF of next
  std::vector<int> changed_;         // (k) changed base DOFs, increasing
  Eigen::MatrixXd delta_;            // (k x k) R - M on them
  Eigen::PartialPivLU<Eigen::MatrixXd> capacitance_;  // I + G Delta
  int added_ = 0;                    // 3 |a|
  solve::Cholesky added_factor_;     // N_aa
  SparseMatrix coupling_;            // (k x 3|a|) N_oa on the changed rows
  Eigen::VectorXd g_, q_, t_, xb_, ba_, xa_, y_, b_;  // scratch
};

}  // namespace softcut::hybrid
