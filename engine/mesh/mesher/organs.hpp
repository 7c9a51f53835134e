#pragma once
// Organ-like shapes for the mesher, as smooth implicit solids (smooth unions
// and subtractions of ellipsoids; lengths in m, at scale 1):
//   liver          0.19 x 0.13 x 0.08: a domed right lobe, a thin left lobe,
//                  a flattened underside; label 1, a spherical lesion label 2
//                  under the right lobe's dome (lesion_radius 0: none); the
//                  dome's top is near (0.025, 0, 0.045)
//   kidney         0.11 long, bean-shaped with a hilum; cortex label 1 (the
//                  outer 6 mm), medulla label 2
//   knee_ligament  0.035 long along +z from z = 0, an elliptic section 10 x 4
//                  mm at mid-length flaring to its insertions, twisted 90
//                  degrees; label 1 (the paper's ligament, Table 2, as the
//                  tissue looks rather than as a box band)
// Meshed by mesh_shape() at a resolution picked to meet target_tets.
#include <atomic>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "mesh/mesher/mesh_shape.hpp"

namespace softcut::mesh {

struct OrganOptions {
  double scale = 1;                 // every length times this, in (0, 1e6] (1000: a mesh in millimetres)
  int target_tets = 5000;           // picks cell_size (within ~20 %); 0: use cell_size
  double cell_size = 0;             // m, when target_tets is 0
  // Grading (0: uniform): tets fine_ratio x smaller within fine_radius (m)
  // of fine_center (m), e.g. around the operational region.
  Eigen::Vector3d fine_center = Eigen::Vector3d::Zero();
  double fine_radius = 0;
  double fine_ratio = 0.4;
  double lesion_radius = 0.012;     // m at scale 1 (liver only)
  Eigen::Vector3d lesion_center{0.035, -0.005, 0.02};  // m at scale 1 (liver only; must lie inside)
  double sliver_bound_deg = 12;
  unsigned seed = 1;
};

// The organ kinds, for messages and docs.
const std::vector<std::string>& organ_kinds();

// The implicit shape of `kind` (throws naming the kind for an unknown one).
LabeledShape organ_shape(const std::string& kind, const OrganOptions& o);

// The mesher options that meet o.target_tets (or use o.cell_size); not
// checked here: estimate_tets and mesh_shape refuse bad ones, naming the shape.
MesherOptions organ_mesher_options(const LabeledShape& s, const OrganOptions& o);

// How large a CGAL mesh may grow and when it must stop.
struct MeshLimit {
  double max_tets = 2147483647.0;  // refused before meshing on the estimate, and after on the count
  // How the caller raises the limit, for the message.
  std::string raise = "softcut run/check --max-tets N raises the limit, --trust lifts it";
  const std::atomic<bool>* stop = nullptr;  // the caller's deadline (MesherOptions::stop)
};

// Meshes `kind`; when target_tets is set and the result is more than 20 %
// off, remeshes once at the corrected size. Refuses (before meshing) a
// request estimated at more than max_tets tetrahedra.
TetMesh generate_organ(const std::string& kind, const OrganOptions& o, const MeshLimit& limit,
                       MesherReport* report = nullptr);
inline TetMesh generate_organ(const std::string& kind, const OrganOptions& o, double max_tets,
                              MesherReport* report = nullptr) {
  MeshLimit limit;
  limit.max_tets = max_tets;
  return generate_organ(kind, o, limit, report);
}

// What generate_organ does for any shape: sizes o's options for `shape`
// (organ_mesher_options), refuses an estimate over the limit, meshes with
// `mesh` (mesh_shape, or another domain's mesher for the same shape), and
// remeshes once at a corrected size when target_tets is missed by > 20 %.
using Mesher = std::function<TetMesh(const MesherOptions&, MesherReport*)>;
TetMesh mesh_to_target(const LabeledShape& shape, const OrganOptions& o, const MeshLimit& limit, const Mesher& mesh,
                       MesherReport* report = nullptr);

// Named node sets of a generated organ (landmarks to put tools and fixes
// on; a scenario selects them with softcut.select.named), from
// the organ's own shape in its axes (lengths below at scale 1):
//   liver          right_lobe, left_lobe (every node, by the nearer lobe);
//                  underside (the flattened face, z <= -0.021), dome (the
//                  surface within 15 mm of the right lobe's top (0.025, 0,
//                  0.045)), lesion (the nodes of label-2 tets; absent without)
//   kidney         hilum (the surface of the hilum's hollow, on +y), convex
//                  (the lateral border: surface with y < -0.02, |x| < 0.035),
//                  upper_pole (x > 0.04), lower_pole (x < -0.04), underside
//                  (z < -0.016), top (z > 0.016): surface nodes
//   knee_ligament  tibial (z <= 0.0005), femoral (z >= 0.0345): its insertions
std::map<std::string, std::vector<int>> organ_landmarks(const std::string& kind, const TetMesh& m,
                                                        const OrganOptions& o);

// "about 12345 tetrahedra, over this run's limit of 2000000; ..." (printable for any count, also inf).
std::string over_limit(double tets, const MeshLimit& limit);

}  // namespace softcut::mesh
