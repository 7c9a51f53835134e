#pragma once
// Pieces of a cut mesh that nothing holds (docs/cutting.md "Pieces cut
// free"). A through-cut can leave a connected part with no fixed node, or
// with fixed nodes only at one point or along one line: it can move rigidly,
// so its stiffness is singular. The cutter does not prevent such cuts (they
// are legitimate surgery); the sim layer finds the pieces after every cut
// step with find_detached and holds them (cut/cut_mesh.hpp).
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::cut {

struct DetachedPiece {
  std::vector<int> tets;   // sorted tet ids
  std::vector<int> nodes;  // sorted ids of the nodes of those tets that no anchored part uses (fixed ones included)
  int fixed_nodes = 0;     // fixed nodes among `nodes`: none, or all at one point or on one line
};

// Rigid parts of `m` (tets joined through faces, fem::anchor_parts) that
// nothing anchors: no fixed node, fixed nodes only at one point or on one line,
// or hanging from the rest of the body by a single node or edge (a hinge).
// `nodes` are the piece's nodes that belong to no anchored part (a hinge node
// stays with the body). Ordered by smallest node id; empty when every part is
// anchored. Throws softcut::Error when node_fixed does not have one entry per
// node.
std::vector<DetachedPiece> find_detached(const mesh::TetMesh& m, const std::vector<char>& node_fixed);

}  // namespace softcut::cut
