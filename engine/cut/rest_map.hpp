#pragma once
// Blade poses come in the deformed (world) configuration; cutting happens in
// the rest configuration. This maps points between the two through the
// piecewise-linear deformation of the tets.
#include <Eigen/Core>
#include <vector>

#include "cut/blade.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::cut {

// Rest position of the material point now at `x`: barycentric coordinates of
// x in the deformed tet (rest + displacement) that contains it, applied to the
// rest tet. A point outside the deformed body uses the tet it is least
// outside of (linear extrapolation of that tet's map). Only tets with
// tet_mask[t] != 0 are used (all when empty). `displacement` (nnode x 3), m.
// Brute force, O(ntet) per point: meant for the few points of a blade pose.
// Throws softcut::Error on size mismatch or when no tet is usable.
Eigen::Vector3d deformed_to_rest(const mesh::TetMesh& m, const Eigen::MatrixX3d& displacement,
                                 const Eigen::Vector3d& x, const std::vector<char>& tet_mask = {});

// The tet (tet_mask[t] != 0, all when empty) whose deformed image contains
// `x`, or -1 when x lies outside the deformed body. Brute force with a box
// test first, O(ntet).
int deformed_tet_at(const mesh::TetMesh& m, const Eigen::MatrixX3d& displacement, const Eigen::Vector3d& x,
                    const std::vector<char>& tet_mask = {});

// Every vertex of a swept surface mapped with deformed_to_rest.
SweptSurface deformed_to_rest(const mesh::TetMesh& m, const Eigen::MatrixX3d& displacement,
                              const SweptSurface& s, const std::vector<char>& tet_mask = {});

}  // namespace softcut::cut
