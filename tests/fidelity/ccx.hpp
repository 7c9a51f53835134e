#pragma once
// CalculiX (ccx, Debian's calculix-ccx) as the independent truth of the
// fidelity tests: a deck written from softcut's own mesh (C3D4, one node per
// mesh node), a geometrically nonlinear static step (*STATIC, NLGEOM) with
// the loads and prescribed displacements ramped over it, the displacements
// read back from the .dat file. The convergence controls are tightened far
// below ccx's defaults (0.5 % of the mean force) so that the comparison
// measures the models, not the solvers.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::test {

struct CcxProblem {
  mesh::TetMesh mesh;
  double young = 0, poisson = 0;
  enum class Law { elastic, neo_hooke } law = Law::elastic;  // *ELASTIC (St Venant-Kirchhoff under NLGEOM) or *HYPERELASTIC, NEO HOOKE
  std::vector<int> fixed;                 // node ids held (their prescribed displacement below, else zero)
  Eigen::MatrixX3d prescribed;            // (nnode x 3) m, read on fixed nodes; empty: zero
  Eigen::MatrixX3d forces;                // (nnode x 3) N; empty: none
};

// Runs ccx in `dir` and returns the displacements at the end of the step
// (nnode x 3, m). Fails the test (throws std::runtime_error) when ccx is
// missing or fails, quoting its log.
Eigen::MatrixX3d run_ccx(const CcxProblem& p, const std::filesystem::path& dir);

// The volume of the mesh displaced by u (nnode x 3), m^3.
double deformed_volume(const mesh::TetMesh& m, const Eigen::MatrixX3d& u);

}  // namespace softcut::test
