#pragma once
// Ligament-like band: a flat rectangular section (width x thickness) swept
// along +z, widening towards both ends (the insertions) and twisted about its
// long axis. Structured (along x across x through) cells, each quad of the
// section split into two triangles and extruded into prisms of three tets
// (see extrude.hpp). Surface: a sphere (Euler characteristic 2).
#include <Eigen/Core>

#include "mesh/generate/extrude.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::mesh {

struct BandOptions {
  Eigen::Vector3d base_center = Eigen::Vector3d::Zero();  // centre of the bottom end section, m; long axis +z
  double length = 0.035;     // m
  double width = 0.010;      // m, at mid-length
  double thickness = 0.004;  // m, at mid-length
  // Section scale at the ends relative to mid-length: width x flare,
  // thickness x sqrt(flare), blended by (2 z / length - 1)^4 (>= 1).
  double flare = 1.6;
  double twist_deg = 90.0;  // rotation of the section from one end to the other, degrees
  // Resolution: cells along the length, across the width and through the
  // thickness. When all are 0 they are picked to meet target_tets /
  // target_nodes (0 = no target) with mid-length cells as close to
  // equal-sided as possible; without targets, 2 cells through the thickness.
  int along = 0, across = 0, through = 0;
  int target_tets = 0, target_nodes = 0;
  double jitter = 0.0;  // interior nodes moved by up to jitter * cell size, [0, 0.25)
  unsigned seed = 1;    // jitter random seed (deterministic)
  int label = 1;        // label of every tet
};

// Fills along, across and through; fails on bad options.
// check_target: fail when a target is out of the search's reach
// (check_target_met); false leaves that to the caller (the sandbox checks
// the resolution against its tet limit first).
BandOptions resolve_band(const BandOptions& opt, bool check_target = true);
// Counts for a resolution (along, across, through).
MeshSize band_size(double along, double across, double through);

// Nodes: grid point (iw across, it through) of layer l has id
// iw + (across+1) * (it + (through+1) * l).
// nodes = (a+1)(w+1)(t+1), tets = 6 a w t.
TetMesh generate_band(const BandOptions& opt);

}  // namespace softcut::mesh
