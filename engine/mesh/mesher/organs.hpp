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
#include <string>
#include <vector>

#include "mesh/mesher/mesh_shape.hpp"

namespace softcut::mesh {

struct OrganOptions {
  double scale = 1;                 // every length times this
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

// Meshes `kind`; when target_tets is set and the result is more than 20 %
// off, remeshes once at the corrected size. Refuses (before meshing) a
// request estimated at more than max_tets tetrahedra.
TetMesh generate_organ(const std::string& kind, const OrganOptions& o, double max_tets, MesherReport* report = nullptr);

}  // namespace softcut::mesh
