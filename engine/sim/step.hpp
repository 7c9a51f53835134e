#pragma once
// One frame: tools/collision -> loads -> (cutting, later) -> elastic solve.
#include "sim/model.hpp"

namespace softcut::sim {

// Advances `s` to frame s.frame + 1 at t = frame * dt: updates tools on the
// current deformed surface (last frame's displacements), sums loads and tool
// forces into s.forces, solves, fills s.last / s.stats. Throws softcut::Error
// (naming the load or tool) on bad runtime input, e.g. a non-finite ramp.
void step(const Model& m, State& s);

// Nodal forces (nnode x 3) of the loads at time t (no tools).
Eigen::MatrixX3d load_forces(const Model& m, const State& s, double t);
// The force magnitude each node of a load gets at time t, N (its ramp times
// its scale, split over its nodes unless per_node). Not checked for finiteness.
double load_per_node(const ActiveLoad& l, double t);

}  // namespace softcut::sim
