#pragma once
// Prism extrusion shared by the cylinder, tube and band generators: a 2D
// triangulated cross-section is stacked into layers and each prism is split
// into three tets. The split of every quad side face is decided by the global
// ids of its two bottom corners alone (diagonal from the smaller id at the
// bottom to the larger id at the top), so two prisms sharing a side face split
// it the same way and the mesh is conforming, also across a periodic seam.
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::mesh {

struct Section {
  Eigen::MatrixX3i triangles;  // (ntri x 3) section point ids
  int num_points = 0;          // section points; node id = point + num_points * layer
  std::vector<char> boundary;  // (num_points) point lies on the section's outline
};

// Places section point `point` of layer `layer` (0..layers); `offset` (3) is a
// jitter displacement in [-jitter, jitter]^3 in cell units, which the
// generator scales by its cell sizes (zero for nodes on the body's surface,
// which stay exact).
using PlacePoint = std::function<Eigen::Vector3d(int point, int layer, const Eigen::Vector3d& offset)>;

// Stacks `layers` >= 1 prism layers. Orientation is decided on the unjittered
// positions; with jitter > 0 the interior nodes get random offsets (seeded,
// deterministic) and a tet that would turn non-positive is an Error naming
// `what` (lower the jitter). Every tet gets `label`.
TetMesh extrude_section(const Section& s, int layers, const PlacePoint& place, double jitter, unsigned seed,
                        int label, const char* what);

// Resolution choice shared by the generators: how far (nodes, tets) miss the
// requested counts (0 = not requested), as the larger relative miss, plus a
// mild penalty for elongated cells (`cell` holds the three cell sizes, m).
// Smaller is better.
double resolution_score(long nodes, long tets, int target_nodes, int target_tets, const Eigen::Vector3d& cell);

// Node and tet counts of a generator resolution, as doubles so that computing
// them cannot overflow (the *_size functions of each generator).
struct MeshSize {
  double nodes = 0, tets = 0;
};

// Fails, naming `what`, when a mesh of that size would not fit int ids.
void check_mesh_size(const char* what, const MeshSize& size);

// How far a resolution picked for targets may miss each target given (a
// fraction): further off, the target is out of the generator's reach.
inline constexpr double kTargetTolerance = 0.25;

// Fails naming `what` when the resolution picked (`nodes`, `tets`) misses a
// target (0: none) by more than kTargetTolerance, saying what it would give
// and that cell counts give any resolution: a target of 1e9 tets silently
// gave the search's largest tube (2.5M tets).
void check_target_met(const char* what, long nodes, long tets, int target_nodes, int target_tets, const char* cells);
inline void check_target_met(const char* what, const MeshSize& size, int target_nodes, int target_tets, const char* cells) {
  check_target_met(what, long(size.nodes), long(size.tets), target_nodes, target_tets, cells);
}

}  // namespace softcut::mesh
