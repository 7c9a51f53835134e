#pragma once
// Saying when a model is out of its depth (DESIGN.md §1b): per frame, the
// largest rotation and strain that linear elasticity is asked to carry, in
// the tets solved with the linear law (the operational region's linear tets,
// or all of a linear whole-mesh solve) and in the condensed region (linear
// by construction: its rotation says whether the operational region is large
// enough). Linear elasticity inflates a tet rotated by theta by about
// theta^2 and is trustworthy below a few degrees and a few percent.
#include <vector>

#include "sim/model.hpp"

namespace softcut::sim {

// Bounds past which a run warns (documented in docs/fidelity.md).
constexpr double kLinearRotationBoundDeg = 5.0;   // linear-law tets
constexpr double kLinearStrainBound = 0.05;       // linear-law tets, |principal strain|
constexpr double kCondensedRotationBoundDeg = 10.0;  // the condensed region

struct Validity {
  double linear_rotation = 0;     // rad, largest over the linear-law tets solved this frame
  double linear_strain = 0;       // largest |principal strain| of those
  int linear_tet = -1;            // the tet of the largest rotation, -1: none
  double condensed_rotation = 0;  // rad, largest over the condensed tets whose nodes are all solved this frame
  int condensed_tet = -1;
};

// From the frame's displacements (the infinitesimal rotation |skew grad u|
// and the largest |eigenvalue| of sym grad u: what the linear law itself
// sees). Condensed tets with an interior node count only when the solver
// recovers the interior (Solver::interior_valid()).
Validity measure_validity(const Model& m, const State& s);

}  // namespace softcut::sim
