#pragma once
// Tet meshes of a SurfaceDomain (closed surfaces a user brings) with CGAL's
// Mesh_3 over a polyhedral complex: each surface is a patch between the two
// labels on its sides, sharp edges (dihedral angle past 60 degrees, a cube's
// or a cut's) are detected and protected, so the tets keep them; the same
// sizing, quality and bounds as the organ shapes (mesh_shape.hpp).
#include "mesh/mesher/mesh_shape.hpp"
#include "mesh/mesher/organs.hpp"
#include "mesh/mesher/surface_domain.hpp"

namespace softcut::mesh {

// Meshes the domain with `o` (checked as mesh_shape checks it). Tets keep the
// label of the region they fill; the boundary's nodes lie on the surfaces.
TetMesh mesh_surface(const SurfaceDomain& d, const MesherOptions& o, MesherReport* report = nullptr);

// The sizing of the organ kinds (target_tets or cell_size, grading, sliver
// bound, seed; o.scale and the lesion options do not apply: give the unit
// and scale when reading) with generate_organ's bounds and one remesh.
TetMesh generate_surface(const SurfaceDomain& d, const OrganOptions& o, const MeshLimit& limit,
                         MesherReport* report = nullptr);

}  // namespace softcut::mesh
