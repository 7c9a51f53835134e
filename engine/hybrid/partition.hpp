#pragma once
// Operational / nonoperational split of a tet mesh (paper §4.1, DESIGN.md §1).
// The operational region is a set of tets; every node referenced by some tet
// falls into exactly one node set:
//   fixed        prescribed zero displacement (eliminated everywhere)
//   operational  "1": free, touched only by operational tets
//   interface    "I": free, touched by operational and nonoperational tets
//   surface      "s": free, nonoperational only, on the outer boundary surface
//                     of the whole body (faces used by exactly one tet)
//   interior     "i": free, nonoperational only, not on that surface
// Nodes referenced by no tet are in no set (NodeSet::unused).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::hybrid {

enum class NodeSet : signed char { unused = -1, fixed, operational, interface, surface, interior };
const char* to_string(NodeSet s);

// Operational tet masks (ntet), 1 = operational. Predicates test tet centroids.
std::vector<char> tets_with_label(const mesh::TetMesh& m, int label);
std::vector<char> tets_in_sphere(const mesh::TetMesh& m, const Eigen::Vector3d& center, double radius);
std::vector<char> tets_in_box(const mesh::TetMesh& m, const Eigen::Vector3d& min_corner,
                              const Eigen::Vector3d& max_corner);
// Centroids c with (c - point) . normal >= 0.
std::vector<char> tets_in_half_space(const mesh::TetMesh& m, const Eigen::Vector3d& point,
                                     const Eigen::Vector3d& normal);
// Explicit tet ids; throws naming the first id out of range.
std::vector<char> tets_from_list(const mesh::TetMesh& m, const std::vector<int>& tet_ids);

// Table 2 of the paper, plus our finer node sets.
struct PartitionCounts {
  int operational_tets = 0, nonoperational_tets = 0;
  int operational_region_nodes = 0;     // nodes of operational tets (sets 1, I and fixed ones)
  int nonoperational_region_nodes = 0;  // nodes of nonoperational tets (sets I, s, i and fixed ones)
  int nonoperational_surface_nodes = 0; // nodes of the latter on the outer surface (incl. fixed, I)
  int fixed = 0, operational = 0, interface = 0, surface = 0, interior = 0, unused = 0;
};

struct Partition {
  std::vector<char> operational_tet;  // (ntet) 1 for operational tets
  std::vector<NodeSet> node_set;      // (nnode) set of each node
  std::vector<int> operational_tets;  // ids of operational tets, increasing
  std::vector<int> nonoperational_tets;
  // Node ids of each set, increasing. The hybrid DOF blocks follow these orders.
  std::vector<int> fixed, operational, interface, surface, interior;
  PartitionCounts counts;

  int num_nodes() const { return int(node_set.size()); }
};

// Builds the node sets from an operational tet mask (ntet; empty = no
// operational tet) and the fixed node ids (ids of unreferenced nodes are
// ignored). Throws softcut::Error for unknown node ids, a mask of the wrong
// size, and a connected part of the body that has no fixed node or whose
// fixed nodes lie on one line (a singular stiffness matrix): the message names
// a node of the part, its tet count per region and its bounding box.
Partition make_partition(const mesh::TetMesh& m, const std::vector<char>& operational_tet,
                         const std::vector<int>& fixed_nodes);

// "operational 40 nodes / 71 tets; nonoperational 575 nodes / 438 surface / 1829 tets; ..."
std::string describe(const PartitionCounts& c);

}  // namespace softcut::hybrid
