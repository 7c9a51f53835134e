#pragma once
// Implicit tool springs: a grasper spring solved exactly within the frame.
//
// The model is linear, so with the grasped DOFs g (3 per free node of the
// grip points' triangles) the displacement is u = u0 + R h, where u0 is the
// response to every other load of the frame, h (3m) the spring forces on
// those nodes and R (3 nnode x 3m) the unit-load responses
// (Solver::unit_responses); C = R_g (3m x 3m) is their compliance block. A
// grip point p (tools::SurfacePoint) sits at X_p + W_p u_g (barycentric
// weights W) and its spring pulls it with f_p = k_p (T_p - X_p - W_p u_g),
// stiffness k_p (the tool's stiffness over its points), target T_p (tip +
// grasp offset); the nodes take h = W^T f. So
//     (diag(1/k) + W C W^T) f = T - X - W u0_g,
// a small SPD system, exact for any stiffness; as k grows f tends to the
// force that puts the points on their targets. R is cached in
// State::springs while the grasped node set and the solver's system
// (cutting changes it) stay the same: a grasper keeps its grip, so R costs
// 3m extra solves once per grasp and a 3 nnode x 3m product per frame.
#include "sim/model.hpp"

namespace softcut::sim {

// After `s.displacement` holds u0 (the solve without implicit springs):
// solves the implicit springs of the engaged graspers, adds R f to
// s.displacement, sets their ToolState forces (on the final positions) and
// adds them to s.forces. Fixed nodes take no force (their share goes into
// the support). Returns the number of grasped nodes solved for (0: nothing
// to do).
int solve_implicit_springs(const Model& m, State& s);

// The most nodes the implicit graspers may hold together (grip points: twice
// that): each costs 3 solves per grasp and the dense blocks grow with the
// square; past it a clear error asks for a smaller jaw or the force drive.
constexpr size_t kMaxGraspedNodes = 400;

}  // namespace softcut::sim
