#pragma once
// Static linear solve of the whole mesh: K u = f with prescribed displacements
// on fixed nodes. The monolithic reference every hybrid result is checked
// against, and the engine's answer for a body without a hybrid partition.
#include <Eigen/Core>
#include <vector>

#include "fem/material.hpp"
#include "solve/cg.hpp"

namespace softcut::fem {

enum class StaticBackend {
  cholmod,  // sparse Cholesky (CHOLMOD): exact to round-off
  cg,       // CPU conjugate gradient with block-Jacobi preconditioner, to opt.cg.tolerance
};

struct StaticProblem {
  std::vector<int> fixed_nodes;         // (nfixed) node ids whose displacement is prescribed
  Eigen::MatrixX3d fixed_displacement;  // (nfixed x 3) prescribed displacement, m; empty = zero
  Eigen::MatrixX3d forces;              // (nnode x 3) nodal forces, N; empty = zero
};

struct StaticOptions {
  StaticBackend backend = StaticBackend::cholmod;
  solve::CgOptions cg;  // tolerance and iteration cap of the cg backend
};

struct StaticSolution {
  Eigen::MatrixX3d displacement;  // (nnode x 3) m: prescribed on fixed nodes, 0 on nodes in no tet
  Eigen::MatrixX3d reaction;      // (nnode x 3) N: K u - f - f0 on fixed nodes (support forces), 0 elsewhere
  int free_dofs = 0;              // size of the solved system
  int cg_iterations = 0;          // cg backend only
  double cg_relative_residual = 0;
  double assemble_seconds = 0, solve_seconds = 0;
};

// Solves the whole mesh (every tet, materials one per tet): K u = f + f0, f0
// the initial strains' forces (initial_strain_forces). Nodes referenced
// by no tet stay out of the system; a force on such a node is an error (it
// would be lost). Forces on fixed nodes go straight into the support and show
// up in `reaction`. Throws softcut::Error for: fixed ids out of range or
// repeated, sizes that do not match, NaN/Inf forces or displacements, a part
// of the body without enough fixed nodes (see check_anchored), and CG that
// does not reach its tolerance (message gives iterations and residual).
StaticSolution solve_static(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                            const StaticProblem& problem, const StaticOptions& opt = {});

using StrainField = Eigen::Matrix<double, Eigen::Dynamic, 6>;  // (ntet x 6) Voigt [xx yy zz yz zx xy]

// Constant strain of every tet (engineering shears, dimensionless) for a
// displacement field u (nnode x 3, m).
StrainField element_strains(const mesh::TetMesh& m, const Eigen::MatrixX3d& u);
// Stress sigma = D (eps - eps0) of every tet, Pa, same Voigt order (shear
// stresses); eps0 the material's initial strain.
StrainField element_stresses(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                             const Eigen::MatrixX3d& u);

}  // namespace softcut::fem
