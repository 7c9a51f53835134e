#pragma once
// Saying when a model is out of its depth (DESIGN.md §1b): per frame, the
// largest rotation and strain that linear elasticity is asked to carry, in
// the tets solved with the linear law (the operational region's linear tets,
// or all of a linear whole-mesh solve) and in the condensed region (linear
// by construction: its rotation says whether the operational region is large
// enough). Linear elasticity inflates a tet rotated by theta by about
// theta^2 and is trustworthy below a few degrees and a few percent.
#include <string>
#include <vector>

namespace softcut::sim {

struct Model;
struct State;

// Bounds past which a run warns, applied to the 99th percentile over the tets
// (documented in docs/fidelity.md).
constexpr double kLinearRotationBoundDeg = 5.0;   // linear-law tets
constexpr double kLinearStrainBound = 0.05;       // linear-law tets, |principal strain|
constexpr double kCondensedRotationBoundDeg = 10.0;  // the condensed region

struct Validity {
  double linear_rotation = 0;     // rad, largest over the linear-law tets solved this frame
  double linear_strain = 0;       // largest |principal strain| of those
  int linear_tet = -1;            // the tet of the largest rotation, -1: none
  double condensed_rotation = 0;  // rad, largest over the condensed tets whose nodes are all solved this frame
  int condensed_tet = -1;
  // The 99th percentile of each over its tets (what 1 % of them exceed): a
  // sliver at a point load or a cut's edge moves the largest, not this.
  double linear_rotation_p99 = 0, linear_strain_p99 = 0, condensed_rotation_p99 = 0;
};

// From the frame's displacements: the rotation of each tet (the angle of the
// polar rotation of F = I + grad u) and the largest |eigenvalue| of
// sym grad u (the strain the linear law itself sees: 1 - cos theta for a
// rigid rotation by theta). Condensed tets with an interior node count only when the solver
// recovers the interior (Solver::interior_valid()).
Validity measure_validity(const Model& m, const State& s);

// At the end of a run, from s.stats: coded warnings (core/warning.hpp) when
// the 99th percentile of a measure passed its bound above in some frame:
// linear_large_rotation,
// linear_large_strain (the linear law carried it; a nonlinear model would
// not), condensed_rotation (the condensed region, linear by construction,
// rotated: the operational region is too small for the motion).
std::vector<std::string> validity_warnings(const Model& m, const State& s);

// validity.csv (docs/outputs.md): one row per frame, the frame's solve
// (CG or PCG iterations, Newton steps; 0 for a linear frame) and
// s.last_validity in degrees and plain strain.
extern const char* const kValidityLogHeader;
std::string validity_log_row(const State& s);

}  // namespace softcut::sim
