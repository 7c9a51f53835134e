#pragma once
// The whole-mesh system, written once: the monolithic reference every hybrid
// result is checked against, the baseline every benchmark measures, and the
// general static problem (DESIGN.md):
//     K u = f + f0   over every tet,
// f0 the tets' initial strains' and body forces' nodal loads, with the fixed
// nodes eliminated (their displacement prescribed: zero, or given) and the
// nodes of no tet left out. Precompute (assemble, eliminate, factor) once,
// then solve per load; the support forces of the fixed nodes come back as
// reactions.
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "fem/grip_springs.hpp"
#include "fem/material.hpp"
#include "fem/nonlinear_tets.hpp"
#include "mesh/tet_mesh.hpp"
#include "solve/cg.hpp"
#include "solve/cholesky.hpp"
#include "solve/newton.hpp"

namespace softcut::fem {

// The system (no factor): what the CG baseline and the direct solver share.
class WholeMesh {
 public:
  // node_fixed: (nnode) nonzero = displacement prescribed (zero unless a
  // `prescribed` field says otherwise). tet_material: (ntet).
  WholeMesh(const mesh::TetMesh& m, const std::vector<Material>& tet_material, const std::vector<char>& node_fixed);

  int num_nodes() const { return nnode_; }
  const DofMap& dofs() const { return map_; }   // the free DOFs
  const SparseMatrix& K() const { return K_; }  // (free x free) N/m, both triangles

  // The right-hand side f + f0 - K_fp u_p on the free DOFs (N) for nodal
  // forces (nnode x 3, N; rows of fixed and unused nodes are dropped) and
  // prescribed displacements (nnode x 3, m, read on the fixed nodes; empty:
  // zero).
  Eigen::VectorXd load(const Eigen::MatrixX3d& forces, const Eigen::MatrixX3d& prescribed = {}) const;
  // A field (nnode x 3, m) from free-DOF values: `prescribed` on the fixed
  // nodes (empty: zero), zero on unused nodes.
  Eigen::MatrixX3d field(const Eigen::VectorXd& x, const Eigen::MatrixX3d& prescribed = {}) const;
  // Support forces (nnode x 3, N): K u - f - f0 on the fixed nodes of the
  // body, zero elsewhere (u: the whole field, as field() gives it).
  Eigen::MatrixX3d reactions(const Eigen::MatrixX3d& u, const Eigen::MatrixX3d& forces) const;
  double assemble_ms() const { return assemble_ms_; }  // assembly and elimination, ms

 private:
  int nnode_ = 0;
  double assemble_ms_ = 0;
  DofMap map_;             // free DOFs
  std::vector<char> node_fixed_;  // (nnode) as given
  DofMap fixed_;           // fixed DOFs of nodes in some tet
  SparseMatrix K_;         // (free x free)
  SparseMatrix K_fp_;      // (free x fixed): prescribed displacements' loads, and reactions
  SparseMatrix K_pp_;      // (fixed x fixed)
  Eigen::VectorXd f0_;     // (free) N: initial strains' and body forces' loads; empty when none
  Eigen::VectorXd f0_p_;   // (fixed) N: the same on the fixed DOFs
};

// The system with a kept CHOLMOD factor: one forward/backward solve per load.
// The factor is read only; each thread that solves brings its workspace.
class WholeMeshSolver {
 public:
  // `what` names the matrix in a factor error; `max_bytes` bounds the factor
  // (solve::Cholesky::factor).
  WholeMeshSolver(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                  const std::vector<char>& node_fixed, const std::string& what = "whole-mesh stiffness",
                  double max_bytes = std::numeric_limits<double>::infinity());

  const WholeMesh& system() const { return sys_; }
  const solve::Cholesky& factor() const { return factor_; }  // of K (benchmarks time its solve alone)
  // u (nnode x 3, m) for nodal forces (nnode x 3, N) and prescribed
  // displacements (WholeMesh::load); the relative residual |f - K x| / |f|
  // of the solve in *relative_residual (0 for no load).
  Eigen::MatrixX3d solve(const Eigen::MatrixX3d& forces, solve::SolveWorkspace& ws,
                         const Eigen::MatrixX3d& prescribed = {}, double* relative_residual = nullptr) const;
  // (3 nnode x 3 nodes.size()) m/N: the displacement field of 1 N on each
  // DOF of `nodes` (f0 not included). Throws naming a fixed or unused node.
  Eigen::MatrixXd unit_responses(const std::vector<int>& nodes, solve::SolveWorkspace& ws) const;
  double factor_ms() const { return factor_ms_; }  // the CHOLMOD factorization, ms

 private:
  WholeMesh sys_;
  double factor_ms_ = 0;
  solve::Cholesky factor_;  // of K; unfactored when no DOF is free
};

// The mixed model on the whole mesh (fem/whole_mesh_newton.cpp): the tets of
// `set` by their laws (and every tet with a moving fixed corner in it), the
// rest linear, grasper springs inside; Newton preconditioned by the kept
// linear factor (solve/newton.hpp). x: the free DOFs' values, the warm start
// in and the solution out (resized from zero when its size differs). The
// unknown node of mesh node n is lin.system().dofs().reduced[3 n] / 3.
// Throws softcut::Error starting with `what` when Newton does not converge.
struct NonlinearSolve {
  const WholeMeshSolver* linear = nullptr;
  const NonlinearTets* set = nullptr;
  const GripSprings* springs = nullptr;  // null: none
  const Eigen::VectorXd* start = nullptr;  // a predicted start (solve::newton, SecantStart); null: x
  solve::NewtonOptions options;
};
solve::NewtonReport solve_nonlinear(const NonlinearSolve& sys, const Eigen::MatrixX3d& forces,
                                    const Eigen::MatrixX3d& prescribed, Eigen::VectorXd& x, NonlinearWork& work,
                                    solve::SolveWorkspace& ws, const std::string& what);
// The unknown node of each mesh node of a whole-mesh system (-1: fixed or unused).
std::vector<int> unknown_nodes(const WholeMesh& sys);

// One direct solve of the whole mesh: (nnode x 3) m.
Eigen::MatrixX3d solve_whole_mesh(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                  const std::vector<char>& node_fixed, const Eigen::MatrixX3d& forces);
// The same system by block-Jacobi PCG from a zero start; iterations in *iterations.
Eigen::MatrixX3d solve_whole_mesh_cg(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                     const std::vector<char>& node_fixed, const Eigen::MatrixX3d& forces,
                                     const solve::CgOptions& opt, int* iterations = nullptr);

// The general static problem on checked input, through the same system:
// listed fixed nodes with their prescribed displacements, forces, and the
// support reactions back.
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
};

// Throws softcut::Error for: fixed ids out of range or repeated, sizes that
// do not match, NaN/Inf forces or displacements, a force on a node of no tet
// (it would be lost), a part of the body without enough fixed nodes (see
// check_anchored), and CG that does not reach its tolerance.
StaticSolution solve_static(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                            const StaticProblem& problem, const StaticOptions& opt = {});

}  // namespace softcut::fem
