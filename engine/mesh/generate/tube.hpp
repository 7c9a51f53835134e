#pragma once
// Thick tube with a coaxial hole: a structured polar grid (radial x around x
// layers, periodic around the axis) whose quads are split into two triangles
// and extruded into prisms of three tets each (see extrude.hpp). This is the
// upper-leg model of the paper: soft tissue around a bone, with the nodes on
// the hole's surface fixed. Surface: a torus (Euler characteristic 0).
#include <Eigen/Core>
#include <vector>

#include "mesh/generate/extrude.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::mesh {

struct TubeOptions {
  Eigen::Vector3d base_center = Eigen::Vector3d::Zero();  // axis point on the bottom face, m; axis +z
  double inner_radius = 0.012;                            // hole radius, m
  double outer_radius = 0.024;                            // m
  double length = 0.03;                                   // m
  // Resolution: cells across the wall, around the axis (>= 3) and along it.
  // When all are 0 they are picked to meet target_tets / target_nodes
  // (0 = no target) with cells as close to equal-sided as possible; without
  // targets, 2 cells across the wall.
  int radial = 0, around = 0, layers = 0;
  int target_tets = 0, target_nodes = 0;
  double jitter = 0.0;  // interior nodes moved by up to jitter * cell size, [0, 0.25)
  unsigned seed = 1;    // jitter random seed (deterministic)
  int label = 1;        // label of every tet
};

// Fills radial, around and layers; fails on bad options.
// check_target: fail when a target is out of the search's reach
// (check_target_met); false leaves that to the caller (the sandbox checks
// the resolution against its tet limit first).
TubeOptions resolve_tube(const TubeOptions& opt, bool check_target = true);
// Counts for a resolution (radial, around, layers).
MeshSize tube_size(double radial, double around, double layers);

// Nodes: grid point (ir across the wall from the hole, it around) of layer l
// has id ir + (radial+1) * (it + around * l); ir == 0 lies on the hole.
// nodes = (nr+1) nt (nl+1), tets = 6 nr nt nl.
TetMesh generate_tube(const TubeOptions& opt);

// The hole-surface nodes (to be fixed, like the paper's thighbone nodes):
// ids of the nodes of `m` within 1e-4 * (outer - inner radius) of the inner radius of
// `opt` and between its end faces, sorted. Works on a generated tube and on
// one written and read back.
std::vector<int> tube_hole_nodes(const TetMesh& m, const TubeOptions& opt);

}  // namespace softcut::mesh
