#pragma once
// Implicit tool springs: a grasper spring solved exactly within the frame.
//
// The model is linear, so with the grasped DOFs g (3 per grasped node) the
// displacement is u = u0 + R f, where u0 is the response to every other load
// of the frame, f (3m) the spring forces on the grasped nodes and R
// (3 nnode x 3m) the unit-load responses (Solver::unit_responses); C = R_g
// (3m x 3m) is the compliance block of the grasped DOFs. Node n's springs
// (summed over tools) pull with f_n = K_n (T_n - X_n - u_n): stiffness K_n,
// stiffness-weighted target T_n. So
//     (diag(1/K) + C) f = T - X_g - u0_g,
// a small SPD system (C is SPD), exact for any stiffness; as K grows f tends
// to the force that puts the nodes on their targets. R is cached in
// State::springs while the grasped node set and the solver's system
// (cutting changes it) stay the same: a grasper keeps its nodes, so R costs
// 3m extra solves once per grasp and a 3 nnode x 3m product per frame.
#include "sim/model.hpp"

namespace softcut::sim {

// After `s.displacement` holds u0 (the solve without implicit springs):
// solves the implicit springs of the engaged graspers, adds R f to
// s.displacement, sets their ToolState forces (on the final positions) and
// adds them to s.forces. Fixed grasped nodes take no force. Returns the
// number of grasped nodes solved for (0: nothing to do).
int solve_implicit_springs(const Model& m, State& s);

}  // namespace softcut::sim
