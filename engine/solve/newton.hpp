#pragma once
// Newton's method for a nonlinear system r(x) = b - F(x) = 0 whose tangent
// T(x) = dF/dx differs from a kept, factored matrix P by a sparse part
// (DESIGN.md §1b): the large-deformation frame, where P is the linear model's
// system (its Cholesky factor kept) and T - P lives on the nonlinear tets only.
//
// Each Newton step solves T d = r by PCG preconditioned with P^-1, applied
// through the caller's factor. The products T p are formed without P: PCG's
// direction p is z + beta p_old with z = P^-1 r, so P p = r + beta P p_old
// is carried along, and T p = P p + (T - P) p costs one sparse product
// (never the dense interface block K' a product with P would read). Where the
// tangent is not positive definite (CG meets negative curvature: a buckling
// or inverted state) the step is redone with the positive semidefinite
// projection of the element tangents. A backtracking line search accepts a
// step that lowers |r| or, where the problem has an energy, the energy
// (a projected step descends the energy, not always |r|). Not converging is
// an error, never a result.
#include <Eigen/Core>
#include <functional>
#include <string>

namespace softcut::solve {

struct NewtonProblem {
  // r = b - F(x) (both of the system's size) with the exact tangent at x
  // formed for tangent_difference; returns the energy whose gradient is -r
  // (J; NaN where the problem has none). May throw.
  std::function<double(const Eigen::VectorXd& x, Eigen::VectorXd& r)> residual;
  // Replaces the tangent of the last residual() call by a positive
  // semidefinite one (the projection of its element tangents).
  std::function<void()> project;
  // y = (T - P) p with the tangent formed last (y sized, zero on entry).
  std::function<void(const Eigen::VectorXd& p, Eigen::VectorXd& y)> tangent_difference;
  // z = P^-1 r (z sized by the callee).
  std::function<void(const Eigen::VectorXd& r, Eigen::VectorXd& z)> precondition;
  // y = P p (y sized, zero on entry). Empty: `precondition` applies P^-1
  // exactly and P p is carried along as above. Set: `precondition` is only
  // an approximation of P^-1 (block Jacobi, where no factor is kept: the CG
  // backends) and T p = P p + (T - P) p is formed with this product.
  std::function<void(const Eigen::VectorXd& p, Eigen::VectorXd& y)> apply_base;
  // The residual's scale, N: convergence is |r| <= tolerance * scale (the
  // norms of the terms r is the difference of: loads and internal forces).
  std::function<double(const Eigen::VectorXd& x)> scale;
};

struct NewtonOptions {
  double tolerance = 1e-10;    // relative residual |r| / scale at convergence
  int max_iterations = 40;     // Newton steps
  int max_cg_iterations = 500; // per step
  // Inexact Newton: each step's CG stops at |T d - r| <= forcing |r|, with
  // forcing = min(max_forcing, |r| / scale) (quadratic convergence kept).
  double max_forcing = 1e-2;
  int max_line_search = 12;    // halvings of a step
  // Below this relative residual a step that no longer halves |r| (or finds
  // no decrease at all) ends the solve as converged: |r| is then at the
  // rounding floor of its own evaluation. Sums with cancelling terms (the
  // dense condensed blocks, prestressed or rotated tets whose forces cancel
  // at a node) put that floor near 1e-10 on some meshes, where insisting on
  // `tolerance` only spins (measured on the shipped ligament_cut and
  // tensioned_incision with a nonlinear law: 1.3e-10 and 3.7e-10 after 40
  // steps). Reported as NewtonReport::at_floor.
  double floor_tolerance = 1e-8;
};

struct NewtonReport {
  int iterations = 0;            // Newton steps taken
  int cg_iterations = 0;         // PCG iterations, all steps
  int line_search_cuts = 0;      // step halvings, all steps
  int projected_steps = 0;       // steps that needed the projected tangent
  double relative_residual = 0;  // |r| / scale at the end
  bool at_floor = false;         // ended at the rounding floor (above tolerance, below floor_tolerance)
};

// Solves from x (the warm start; the result is left in x). Throws
// softcut::Error starting with `what` when |r| does not fall below the
// tolerance within the options' limits, or the residual is not finite.
// `start` (optional, x's size): a predicted start (SecantStart); the solve
// begins there and falls back to x if Newton fails from it, the failed
// attempt's work counted.
NewtonReport newton(const NewtonProblem& p, Eigen::VectorXd& x, const NewtonOptions& opt = {},
                    const std::string& what = "Newton solve", const Eigen::VectorXd* start = nullptr);

// The start of each frame's Newton solve of one system, predicted from the
// frames before: x_n + theta (x_n - x_{n-1}), theta how the last increment
// continued the one before it (their least-squares ratio, clamped to
// [0, 1]), once two increments in a row continued the one before them
// (ratio 0.5 .. 1.5): a load that ramps. A ramped load then starts each
// frame O(dt^2) off instead of O(dt): box_111132 pressed over 30 frames,
// 2.9 -> 2.1 Newton steps a frame. A plain secant (theta = 1 always)
// overshot where cuts and tools moving in jerks broke the trend: the shipped
// through_cut and tensioned_incision took 1.5 -> 2.2 and 1.4 -> 2.6 steps a
// frame with it.
class SecantStart {
 public:
  // Forget the history (a new system: a cut, or a frame solved otherwise).
  void clear();
  // The predicted start of the solve that follows the solution x; null
  // when there is nothing to predict from (valid until the next call).
  const Eigen::VectorXd* predict(const Eigen::VectorXd& x);
  // After that solve: the solution it started from and the one it found.
  void record(const Eigen::VectorXd& from, const Eigen::VectorXd& solution);
  double theta() const { return theta_; }

 private:
  Eigen::VectorXd increment_;  // x_n - x_{n-1}; empty: unknown
  Eigen::VectorXd start_;
  double theta_ = 0;
  int steady_ = 0;  // increments in a row that continued the one before
};

}  // namespace softcut::solve
