#pragma once
// Pieces of a cut mesh that nothing holds (docs/cutting.md "Pieces cut
// free"). A through-cut can leave a connected part with no fixed node, or
// with fixed nodes only at one point or along one line: it can move rigidly,
// so its stiffness is singular. The cutter does not prevent such cuts (they
// are legitimate surgery); the sim layer finds the pieces after every cut
// step with find_detached and holds them (sim/cutting.hpp).
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::cut {

struct DetachedPiece {
  std::vector<int> tets;   // sorted tet ids
  std::vector<int> nodes;  // sorted ids of every node of those tets (fixed ones included)
  int fixed_nodes = 0;     // fixed nodes among `nodes`: none, or all at one point or on one line
};

// Connected parts of `m` (tets sharing a node, as hybrid::make_partition
// counts them) whose fixed nodes (node_fixed, nnode, nonzero = fixed) do not
// pin all six rigid motions: none, all within 1e-9 x (part diagonal) of one
// point, or of one line. Ordered by smallest node id; empty when every part is
// anchored. Parts joined only through a node or an edge count as one part
// (the cutter separates a node around which all faces are cut). Throws
// softcut::Error when node_fixed does not have one entry per node.
std::vector<DetachedPiece> find_detached(const mesh::TetMesh& m, const std::vector<char>& node_fixed);

}  // namespace softcut::cut
