#pragma once
// Element quality measures used to guard cutting against slivers (they ruin
// the conditioning of the operational system and so CG convergence).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mesh/tet_mesh.hpp"

namespace softcut::cut {

// Smallest of the six interior dihedral angles, degrees (70.53 for a regular
// tet, 45 for a Kuhn cube tet, 0 for a flat one). Negative orientation does
// not matter; a degenerate tet gives 0.
double min_dihedral_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                        const Eigen::Vector3d& d);
double min_dihedral_deg(const mesh::TetMesh& m, int tet);

// Volume-length ratio 6*sqrt(2)*V / l_rms^3: 1 for a regular tet, 0 when flat,
// negative when inverted.
double volume_length_ratio(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                           const Eigen::Vector3d& d);
double volume_length_ratio(const mesh::TetMesh& m, int tet);

}  // namespace softcut::cut
