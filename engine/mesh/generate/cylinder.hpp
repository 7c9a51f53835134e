#pragma once
// Solid circular cylinder. The cross-section is a hexagonal disk triangulation
// (a centre point and rings of 6k points, k = 1..rings, near-equilateral
// triangles, no degenerate axis), extruded in layers along +z and split into
// three tets per prism (see extrude.hpp). Surface: a sphere (Euler characteristic 2).
#include <Eigen/Core>

#include "mesh/generate/extrude.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::mesh {

struct CylinderOptions {
  Eigen::Vector3d base_center = Eigen::Vector3d::Zero();  // centre of the bottom disk, m; axis +z
  double radius = 0.02;                                   // m
  double length = 0.06;                                   // m
  // Resolution: rings across the radius and layers along the axis. When both
  // are 0 they are picked to meet target_tets / target_nodes (0 = no target)
  // with cells as close to equal-sided as possible; without targets, 4 rings.
  int rings = 0, layers = 0;
  int target_tets = 0, target_nodes = 0;
  double jitter = 0.0;  // interior nodes moved by up to jitter * cell size, [0, 0.25)
  unsigned seed = 1;    // jitter random seed (deterministic)
  int label = 1;        // label of every tet
};

// Fills rings and layers (from the targets when they are 0); fails on bad options.
// check_target: fail when a target is out of the search's reach
// (check_target_met); false leaves that to the caller (the sandbox checks
// the resolution against its tet limit first).
CylinderOptions resolve_cylinder(const CylinderOptions& opt, bool check_target = true);
// Counts for a resolution (rings, layers).
MeshSize cylinder_size(double rings, double layers);

// Nodes: section point p (0 = centre, then ring by ring, counter-clockwise) of
// layer l has id p + (1 + 3 rings (rings + 1)) * l.
// nodes = (1 + 3 R (R+1)) (L+1), tets = 18 R^2 L for R rings, L layers.
TetMesh generate_cylinder(const CylinderOptions& opt);

}  // namespace softcut::mesh
