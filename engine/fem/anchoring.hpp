#pragma once
// Connected parts of a tet set and the check that each is held by fixed nodes.
// A part that can move rigidly makes K singular; CHOLMOD may not notice (round
// off turns the zero pivots into tiny positive ones) and CG would drift, so
// every solve checks the topology first and names the part.
#include <Eigen/Core>
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

// Rigid parts and what holds them. Tets sharing a face are one rigid part; two
// parts that share only a node or an edge can turn about it (a hinge). A part
// is anchored when its pinned nodes include three not on one line (within
// 1e-9 x its diagonal); pinned are its fixed nodes and the nodes it shares with
// anchored parts, so anchoring spreads through shared nodes: a part held by
// two edges on different lines, or hanging from a face, is anchored; one
// hanging by a single node or edge is not.
struct Anchoring {
  enum class Pin { none, point, line };
  struct Part {
    int tets = 0;
    int first_node = -1;      // smallest node id
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);  // m
    int fixed = 0;            // own fixed nodes
    bool anchored = false;
    Pin pin = Pin::none;      // unanchored parts: what holds them (none, one point, one line)
    int pin_a = -1, pin_b = -1;  // the pinned node(s) of `pin`
    bool through_shared = false; // a pinned node is shared with another part (a hinge)
  };
  std::vector<int> tet_part;   // (ntet) part of each tet of the set, -1 for others
  std::vector<Part> parts;     // in order of their smallest tet id
  // "the part of the body containing node N (T tets, bounding box [..] .. [..] m)"
  std::string describe(int part) const;
  // Why part `p` is not anchored and what to do, e.g. "hangs by the edge 4-9 from the
  // rest of the body, so it can turn about that line ...".
  std::string why_loose(int part) const;
};
Anchoring anchor_parts(const mesh::TetMesh& m, const std::vector<int>& tets, const std::vector<char>& node_fixed);

// Throws softcut::Error naming `what` and the part (its smallest node id, tet
// count and bounding box) unless every rigid part is anchored (anchor_parts:
// one point or a line leaves a rotation free, also a hinge to the rest of the
// body). node_fixed: (nnode) nonzero for fixed nodes.
void check_anchored(const mesh::TetMesh& m, const std::vector<int>& tets, const std::vector<char>& node_fixed,
                    const std::string& what);

}  // namespace softcut::fem
