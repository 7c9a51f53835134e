#pragma once
// Stage 4 of a nonlinear frame (DESIGN.md §1b): the operational system with
// its nonlinear tets (OperationalSystem::nonlinear), solved by Newton. The
// condensed region stays linear and exact: K' and P' enter as in the linear
// frame, so
//     r(x) = b - (K + K') x - d(x) + springs(x) = 0,
// b the linear frame's right-hand side ([P1; PI - P'] + initial strains and
// body forces), d the nonlinear tets' correction (fem/nonlinear_tets.hpp),
// springs the graspers holding operational nodes (fem/grip_springs.hpp).
// Each Newton step's linear solves go through the run's kept operational
// factor (OperationalSolver::precondition: the linear system's, after cuts
// its low-rank correction), never a refactor.
#include <Eigen/Core>

#include "fem/grip_springs.hpp"
#include "fem/nonlinear_tets.hpp"
#include "hybrid/operational_solvers.hpp"
#include "hybrid/operational_system.hpp"
#include "solve/newton.hpp"

namespace softcut::hybrid {

struct NonlinearFrame {
  Eigen::MatrixX3d prescribed;              // (nnode x 3) m on fixed nodes; empty: none moves
  const fem::GripSprings* springs = nullptr;  // graspers inside the solve; null: none
  solve::NewtonOptions newton;
};

struct NonlinearReport {
  solve::NewtonReport newton;
  double max_rotation = 0;  // rad, of the nonlinear tets at the solution
  double max_strain = 0;    // |stretch - 1|
  int inverted = 0;         // tets with det F <= 0 at the solution
};

// True when this frame of `sys` must be solved by solve_nonlinear: it has
// nonlinear tets, or a fixed corner that moves.
bool needs_nonlinear_solve(const OperationalSystem& sys, const NonlinearFrame& frame);

// Solves r(x) = 0 from x (warm start; resized from zero when its size
// differs), from the predicted `start` when given (solve::newton).
// Throws softcut::Error starting with `what` when Newton does not converge,
// or naming the grasper's node when a grasp holds a node that is not an
// unknown of the operational system. `helper`: the run's second thread,
// which takes half of each element loop (fem::evaluate); same bits without.
NonlinearReport solve_nonlinear(const OperationalSystem& sys, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                OperationalSolver& solver, fem::NonlinearWork& work, const NonlinearFrame& frame,
                                const std::string& what, const Eigen::VectorXd* start = nullptr,
                                HelperThread* helper = nullptr);

}  // namespace softcut::hybrid
