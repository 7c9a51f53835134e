#pragma once
// The whole-mesh system, the monolithic reference every hybrid result is
// checked against and the baseline every benchmark measures (DESIGN.md):
//     K u = f + f0   over every tet,
// f0 the tets' initial strains' forces, with the fixed nodes and the nodes
// of no tet eliminated. Written once, used by the engine's monolithic
// backend, the tests and the benchmarks: precompute (assemble, eliminate,
// factor) once, then solve per load. (fem/static_solve is the general static
// problem: prescribed displacements and support reactions.)
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "fem/assembly.hpp"
#include "fem/dof_map.hpp"
#include "fem/material.hpp"
#include "mesh/tet_mesh.hpp"
#include "solve/cg.hpp"
#include "solve/cholesky.hpp"

namespace softcut::fem {

// The system (no factor): what the CG baseline and the direct solver share.
class WholeMesh {
 public:
  // node_fixed: (nnode) nonzero = displacement zero. tet_material: (ntet).
  WholeMesh(const mesh::TetMesh& m, const std::vector<Material>& tet_material, const std::vector<char>& node_fixed);

  int num_nodes() const { return nnode_; }
  const DofMap& dofs() const { return map_; }
  const SparseMatrix& K() const { return K_; }  // (free x free) N/m, both triangles

  // The right-hand side f + f0 on the free DOFs (N) for nodal forces
  // (nnode x 3, N; rows of fixed and unused nodes are dropped).
  Eigen::VectorXd load(const Eigen::MatrixX3d& forces) const;
  // A field (nnode x 3, m) from free-DOF values; zero on fixed and unused nodes.
  Eigen::MatrixX3d field(const Eigen::VectorXd& x) const;
  double assemble_ms() const { return assemble_ms_; }  // assembly and elimination, ms

 private:
  int nnode_ = 0;
  double assemble_ms_ = 0;
  DofMap map_;
  SparseMatrix K_;
  Eigen::VectorXd f0_;  // (free) N: the initial strains' forces; empty when none
};

// The system with a kept CHOLMOD factor: one forward/backward solve per load.
class WholeMeshSolver {
 public:
  // `what` names the matrix in a factor error; `max_bytes` bounds the factor
  // (solve::Cholesky::factor).
  WholeMeshSolver(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                  const std::vector<char>& node_fixed, const std::string& what = "whole-mesh stiffness",
                  double max_bytes = std::numeric_limits<double>::infinity());

  const WholeMesh& system() const { return sys_; }
  const solve::Cholesky& factor() const { return factor_; }  // of K (benchmarks time its solve alone)
  // u (nnode x 3, m) for nodal forces (nnode x 3, N); the relative residual
  // |f - K x| / |f| of the solve in *relative_residual (0 for no load).
  Eigen::MatrixX3d solve(const Eigen::MatrixX3d& forces, double* relative_residual = nullptr) const;
  // (3 nnode x 3 nodes.size()) m/N: the displacement field of 1 N on each
  // DOF of `nodes` (f0 not included). Throws naming a fixed or unused node.
  Eigen::MatrixXd unit_responses(const std::vector<int>& nodes) const;
  double factor_ms() const { return factor_ms_; }  // the CHOLMOD factorization, ms

 private:
  WholeMesh sys_;
  double factor_ms_ = 0;
  solve::Cholesky factor_;  // of K; unfactored when no DOF is free
};

// One direct solve of the whole mesh: (nnode x 3) m.
Eigen::MatrixX3d solve_whole_mesh(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                  const std::vector<char>& node_fixed, const Eigen::MatrixX3d& forces);
// The same system by block-Jacobi PCG from a zero start; iterations in *iterations.
Eigen::MatrixX3d solve_whole_mesh_cg(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                     const std::vector<char>& node_fixed, const Eigen::MatrixX3d& forces,
                                     const solve::CgOptions& opt, int* iterations = nullptr);

}  // namespace softcut::fem
