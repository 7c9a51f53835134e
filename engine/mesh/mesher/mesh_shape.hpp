#pragma once
// Smooth, graded, labelled tet meshes from a LabeledShape with CGAL's Mesh_3
// (Delaunay refinement of the labelled domain, then sliver perturbation and
// exudation). docs/meshing.md says why CGAL and what was measured.
#include <Eigen/Core>
#include <atomic>
#include <cstddef>

#include "core/error.hpp"
#include "mesh/mesher/shape.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::mesh {

struct MesherOptions {
  // Local target size h(p), m: the bound on tet circumradius and surface
  // triangle size. `cell_size` everywhere, or, with fine_radius > 0,
  // `fine_size` within fine_radius of fine_center, growing linearly to
  // cell_size over the next fine_radius (the operational region fine, the
  // condensed remainder coarse).
  double cell_size = 0;
  double fine_size = 0;
  Eigen::Vector3d fine_center = Eigen::Vector3d::Zero();
  double fine_radius = 0;
  double facet_distance = 0.1;   // surface approximation error bound, as a fraction of h(p)
  double facet_angle_deg = 25;   // lower bound on surface triangle angles (<= 30 guarantees termination)
  double radius_edge = 3;        // upper bound on tet circumradius / shortest edge (>= 2)
  double sliver_bound_deg = 12;  // perturbation and exudation try to lift every dihedral angle above this
  double optimise_seconds = 30;  // time limit of each optimisation pass
  unsigned seed = 1;             // the mesher's random numbers: same seed, same mesh
  // Bounds on the refinement (Mesh_3 checks both between insertions): at
  // max_vertices (0: none) it fails naming the count; when *stop turns true
  // (the command's deadline, core/watchdog.hpp) it throws TimeoutError.
  std::size_t max_vertices = 0;
  const std::atomic<bool>* stop = nullptr;
};

struct MesherReport {
  int nodes = 0, tets = 0;
  double min_dihedral_deg = 0;  // smallest dihedral angle of any tet
  double seconds = 0;           // meshing wall time
};

// h(p) of `o`, m (checked options).
double local_size(const MesherOptions& o, const Eigen::Vector3d& p);

// Tets the mesher will make for `s` with `o`, estimated before meshing from
// the volume and h (within ~25 % for smooth shapes; the sandbox refuses an
// over-size request with it before anything is allocated).
double estimate_tets(const LabeledShape& s, const MesherOptions& o);

// Mesh_3's vertices for a mesh of `max_tets` tetrahedra, with room to spare
// (Delaunay refinement leaves 5.5-6 tets per vertex; ~3 at coarse sizes).
std::size_t max_vertices_for(double max_tets);

// After a Mesh_3 refinement with `o`: throws TimeoutError when o.stop is set,
// an Error naming `name` when the vertex bound was reached.
void check_stopped(const std::string& name, const MesherOptions& o, bool vertices_reached);

// Meshes every positive label of `s`: tets keep the label of the region they
// fill; shared boundaries between labels are conforming. Fails naming
// s.name for bad options or an empty result. Nodes are numbered in the order
// tets first use them; the result is validated (positively oriented).
TetMesh mesh_shape(const LabeledShape& s, const MesherOptions& o, MesherReport* report = nullptr);

}  // namespace softcut::mesh
