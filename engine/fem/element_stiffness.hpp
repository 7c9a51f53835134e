#pragma once
// Linear tetrahedron (paper §3.2): constant strain, K_e = V B^T D B.
#include <Eigen/Core>

#include "fem/material.hpp"

namespace softcut::fem {

using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat6x12 = Eigen::Matrix<double, 6, 12>;
using TetCorners = Eigen::Matrix<double, 4, 3>;  // row k = position of local node k, m

// Strain-displacement matrix B (6 x 12), DOF order [n0x n0y n0z n1x ...],
// strain order [xx yy zz yz zx xy] (engineering shears). Writes the signed
// volume (m^3) to *volume when given.
Mat6x12 strain_displacement(const TetCorners& X, double* volume = nullptr);

// Element stiffness (12 x 12), N/m: V B^T D B (computed in closed form for
// the isotropic D), exactly symmetric, positive semidefinite with the six
// rigid motions in its null space. X must be positively oriented (the
// assembler checks this and names the tet).
Mat12 element_stiffness(const TetCorners& X, const Material& mat);

// Rest positions of the four corners of tet t of a mesh.
TetCorners tet_corners(const mesh::TetMesh& m, int t);

}  // namespace softcut::fem
