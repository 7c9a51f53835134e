#pragma once
// Tet mesh of a segmented label image: every voxel whose label is selected
// becomes a cube split into six tets around its main diagonal (Kuhn split,
// the same in every voxel, so neighbours share faces and lattice nodes and the
// mesh is conforming, also across label boundaries). Each tet keeps its
// voxel's label. Optional Taubin smoothing of the outer surface removes the
// staircase while keeping every tet positive.
#include <string>
#include <vector>

#include "core/error.hpp"
#include "mesh/tet_mesh.hpp"
#include "mesh/volume/nrrd.hpp"

namespace softcut::mesh {

struct VoxelMeshOptions {
  std::vector<int> labels;   // labels to mesh; empty: every nonzero label
  int smooth_iterations = 0; // Taubin (lambda 0.5, mu -0.53) passes over the outer surface nodes
  // A smoothing move is taken only if every tet at the node keeps at least
  // this fraction of its voxel-grid volume (halved steps are tried first).
  double min_volume_fraction = 0.2;
  // Tetrahedra the mesh may have (six per selected voxel), checked before
  // anything is allocated for it; the message names `raise`, how to lift it.
  double max_tets = 2147483647.0;
  std::string raise = "--max-tets N raises the limit";
};

// Taubin passes a caller may ask for (each moves every outer-surface node).
inline constexpr int kMaxSmoothIterations = 1000;

// Lattice corner (i, j, k), 0 <= i <= size(0), lies at
// origin + directions * ((i, j, k) - 0.5): voxels are centred on their samples.
// Nodes are numbered in lattice order (i fastest), only those used; tets by
// voxel (i fastest), six per voxel. Fails when a requested label does not
// occur or nothing is selected; warns (into diag) about non-manifold surface
// edges where voxels touch only along an edge.
TetMesh mesh_label_volume(const LabelVolume& v, const VoxelMeshOptions& opt, Diagnostics& diag);

// Moves the outer-surface nodes of `m` by `iterations` Taubin passes; every
// move keeps every tet's volume >= min_volume_fraction * its volume before
// smoothing. Returns the number of moves rejected.
int smooth_surface(TetMesh& m, int iterations, double min_volume_fraction);

}  // namespace softcut::mesh
