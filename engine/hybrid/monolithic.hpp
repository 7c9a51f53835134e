#pragma once
// Reference solutions of the whole mesh, independent of the hybrid
// decomposition: the invariant "hybrid == monolithic" and the benchmark
// baselines use them.
#include <Eigen/Core>
#include <vector>

#include "fem/material.hpp"
#include "mesh/tet_mesh.hpp"
#include "solve/cg.hpp"

namespace softcut::hybrid {

// Direct CHOLMOD solve of K u = f + f0 over all tets (f0: the materials'
// initial strains, fem::initial_strain_forces), fixed nodes (node_fixed,
// nnode) eliminated; returns (nnode x 3) m, zero on fixed and unused nodes.
// forces: (nnode x 3) N.
Eigen::MatrixX3d solve_monolithic(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                  const std::vector<char>& node_fixed, const Eigen::MatrixX3d& forces);

// The same system by block-Jacobi PCG from a zero start; iterations in *iterations.
Eigen::MatrixX3d solve_monolithic_cg(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                     const std::vector<char>& node_fixed, const Eigen::MatrixX3d& forces,
                                     const solve::CgOptions& opt, int* iterations = nullptr);

}  // namespace softcut::hybrid
