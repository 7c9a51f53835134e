#pragma once
// The models the benchmarks time the hybrid on (bench hybrid, bench
// nonlinear): the paper's two (Wu & Heng 2005, Table 2) at their sizes, boxes
// and CGAL livers, each with its fixed nodes and operational region.
#include <Eigen/Core>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::bench {

struct BenchModel {
  mesh::TetMesh mesh;
  std::vector<int> fixed;
  std::vector<char> op_mask;  // (tets) 1: operational
  int center = -1;            // the surface node the operational region is centred on (-1: none)
};

// Sphere around `center` whose centroid test selects about `target` tets.
std::vector<char> sphere_with_tets(const mesh::TetMesh& m, const Eigen::Vector3d& center, int target);
// The surface node closest to p.
int nearest_surface_node(const mesh::TetMesh& m, const Eigen::Vector3d& p);

BenchModel ligament();
BenchModel upper_leg();
// Box of 2n x n x n cells (12 n^3 tets), x = 0 face fixed, operational
// hemisphere of `op_tets` tets at the middle of the top face.
BenchModel box(int n, int op_tets);
// A CGAL liver of about `tets` tets held at the flattened underside of its
// right lobe, operational region of `op_tets` tets under its dome.
BenchModel liver(int tets, int op_tets);

}  // namespace softcut::bench
