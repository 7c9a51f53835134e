#pragma once
// One assembler for every stiffness matrix: the whole mesh, the operational
// tets (K^op) or the nonoperational tets (K^non). DOF numbering is global:
// dof = 3 * node + axis over all nodes of the mesh; nodes outside the tet set
// get empty rows and columns.
#include <Eigen/SparseCore>
#include <vector>

#include "fem/material.hpp"

namespace softcut::fem {

using SparseMatrix = Eigen::SparseMatrix<double>;  // column-major, int indices

// K (3 nnode x 3 nnode), N/m, symmetric, from the tets listed in `tets` (all
// tets when empty). `tet_material` has one entry per tet of the mesh.
// The sparsity pattern is built per 3x3 node block, then element matrices are
// scattered straight into it (no triplet list), so 100k tets take well under
// a second.
SparseMatrix assemble_stiffness(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                const std::vector<int>& tets = {});

// Elastic strain energy 1/2 u^T K u of a displacement field (nnode x 3), J,
// summed element by element (independent of the assembler; used in tests).
double strain_energy(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                     const Eigen::MatrixX3d& u);

}  // namespace softcut::fem
