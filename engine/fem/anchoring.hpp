#pragma once
// Connected parts of a tet set and the check that each is held by fixed nodes.
// A part that can move rigidly makes K singular; CHOLMOD may not notice (round
// off turns the zero pivots into tiny positive ones) and CG would drift, so
// every solve checks the topology first and names the part.
#include <string>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::fem {

struct Parts {
  std::vector<int> node_part;  // (nnode) part of each node, -1 for nodes in no tet of the set
  std::vector<int> tet_count;  // (count) tets per part
  int count = 0;               // parts, numbered in order of their smallest node id
};

// Parts of the tets listed in `tets` (all tets when empty): tets sharing a
// node belong to the same part.
Parts connected_parts(const mesh::TetMesh& m, const std::vector<int>& tets = {});

// Throws softcut::Error naming `what` and the part (its smallest node id, tet
// count and bounding box) unless every part has fixed nodes that are not all
// on one line (one point or a line leaves a rotation free). node_fixed: (nnode)
// nonzero for fixed nodes. Parts joined to others only through a node or an
// edge (hinges) are not detected here.
void check_anchored(const mesh::TetMesh& m, const std::vector<int>& tets, const std::vector<char>& node_fixed,
                    const std::string& what);

}  // namespace softcut::fem
