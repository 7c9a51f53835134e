#pragma once
// Structured box mesh: nx * ny * nz hexahedral cells, each split into six
// tets around the main diagonal (Kuhn / Freudenthal split), so neighbouring
// cells share faces exactly and the mesh is conforming.
#include <Eigen/Core>

#include "mesh/generate/extrude.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::mesh {

struct BoxOptions {
  Eigen::Vector3d min_corner = Eigen::Vector3d::Zero();  // m
  Eigen::Vector3d max_corner = Eigen::Vector3d::Ones();  // m
  int nx = 4, ny = 4, nz = 4;                             // cells per axis, >= 1
  double jitter = 0.0;      // interior nodes moved by up to jitter * cell size (< 0.25)
  unsigned seed = 1;        // jitter random seed (deterministic)
  int label = 1;            // label of every tet
};

// Nodes are numbered x fastest: id = i + (nx+1) * (j + (ny+1) * k).
TetMesh generate_box(const BoxOptions& opt);
// Counts of the mesh generate_box makes.
MeshSize box_size(const BoxOptions& opt);

}  // namespace softcut::mesh
