#pragma once
// Mesh invariants the cut tests check after every step, computed from the
// mesh alone (independently of the cutter's own bookkeeping).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::test {

struct MeshCheck {
  int faces_over_two = 0;      // node triples used by more than two tets
  int open_edges = 0;          // boundary edges not used equally often in both directions
  int hanging_nodes = 0;       // nodes strictly inside a boundary edge or face of their own piece
  int unmatched_boundary = 0;  // boundary faces neither on the box nor with a coincident twin
  int inverted = 0;            // tets with volume <= kDegenerateVolume * (longest edge)^3
  double worst_dihedral = 180;
  double volume = 0;
};

// Conformity, topologically: the boundary of a conforming tet mesh is closed,
// so every boundary edge is used as often from a to b as from b to a by the
// outward-oriented boundary faces; a hanging node (a node inside an edge or
// face of a tet it does not belong to) leaves an edge used one way only.
// Geometrically, for cuts made once: box [lo, hi]; a boundary face is "on the
// box" when its three nodes lie on one side plane, and every other boundary
// face must have a twin, another boundary face with the same three positions
// and the opposite orientation (the two sides of a separated cut). Where a
// blade passes separated sides again, they may be split differently. Also for
// a single cut: no node lies strictly inside a boundary edge or face of the
// piece it belongs to (hanging_nodes). Across a partly opened crack that a
// later blade re-splits, a node of one side may lie on the other side's
// boundary edge without any fault, so that count is meaningful only then.
MeshCheck check_mesh(const mesh::TetMesh& m, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

// Connected components of the tets (adjacency through shared faces);
// comp (ntet) gets each tet's component id; returns the count.
int components(const mesh::TetMesh& m, std::vector<int>* comp = nullptr);

}  // namespace softcut::test
