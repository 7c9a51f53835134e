#include "bench/bench_models.hpp"

#include <algorithm>

#include "bench/box_problem.hpp"
#include "hybrid/partition.hpp"
#include "mesh/generate/presets.hpp"
#include "mesh/mesher/organs.hpp"
#include "mesh/surface.hpp"

namespace softcut::bench {

using hybrid::tets_in_sphere;

std::vector<char> sphere_with_tets(const mesh::TetMesh& m, const Eigen::Vector3d& center, int target) {
  double lo = 0, hi = (m.nodes.colwise().maxCoeff() - m.nodes.colwise().minCoeff()).norm() * 2;
  for (int it = 0; it < 50; ++it) {
    const double r = 0.5 * (lo + hi);
    const auto mask = tets_in_sphere(m, center, r);
    (int(std::count(mask.begin(), mask.end(), 1)) < target ? lo : hi) = r;
  }
  return tets_in_sphere(m, center, hi);
}

int nearest_surface_node(const mesh::TetMesh& m, const Eigen::Vector3d& p) {
  const auto s = mesh::extract_surface(m);
  int best = s.nodes.front();
  for (int v : s.nodes)
    if ((m.node(v) - p).squaredNorm() < (m.node(best) - p).squaredNorm()) best = v;
  return best;
}

// The paper's knee ligament (the band preset, about 1,900 tets), both
// insertions fixed, an operational region of the paper's 71 tets around a
// surface node of its broad face.
BenchModel ligament() {
  BenchModel b{mesh::generate_band(mesh::ligament_preset()), {}, {}};
  const double z0 = b.mesh.nodes.col(2).minCoeff(), z1 = b.mesh.nodes.col(2).maxCoeff();
  for (int v = 0; v < b.mesh.num_nodes(); ++v)  // both insertions fixed
    if (b.mesh.nodes(v, 2) <= z0 + 1e-9 || b.mesh.nodes(v, 2) >= z1 - 1e-9) b.fixed.push_back(v);
  const Eigen::Vector3d mid = b.mesh.nodes.colwise().mean().transpose();
  const int c = nearest_surface_node(b.mesh, mid + Eigen::Vector3d(0.02, 0, 0));
  b.op_mask = sphere_with_tets(b.mesh, b.mesh.node(c), 71);
  b.center = c;
  return b;
}

// The paper's upper leg (the tube preset, about 2,550 tets), the thighbone's
// hole fixed, an operational region of the paper's 416 tets on the front.
BenchModel upper_leg() {
  const mesh::TubeOptions o = mesh::upper_leg_preset();
  BenchModel b{mesh::generate_tube(o), {}, {}};
  b.fixed = mesh::tube_hole_nodes(b.mesh, o);  // the thighbone
  const int c = nearest_surface_node(b.mesh, o.base_center + Eigen::Vector3d(o.outer_radius, 0, 0.5 * o.length));
  b.op_mask = sphere_with_tets(b.mesh, b.mesh.node(c), 416);
  b.center = c;
  return b;
}

// Box of 2n x n x n cells (12 n^3 tets), x = 0 face fixed, operational
// hemisphere of `op_tets` tets at the middle of the top face.
BenchModel box(int n, int op_tets) {
  BoxProblem box = box_problem({{2 * n, n, n}, {0.1, 0.05, 0.05}, 0.1, 0});
  BenchModel b{std::move(box.mesh), std::move(box.fixed), {}};
  b.op_mask = sphere_with_tets(b.mesh, Eigen::Vector3d(0.05, 0.025, 0.05), op_tets);
  return b;
}

// A CGAL liver of about `tets` tets (the organ mesher's, as `softcut mesh
// generate liver --target-tets N`; its tet count is within ~20 % of N), held
// at the flattened underside of its right lobe (z <= -19 mm, as
// scenarios/liver_retraction.lua), operational region of `op_tets` tets
// under the right lobe's dome.
BenchModel liver(int tets, int op_tets) {
  mesh::OrganOptions o;
  o.target_tets = tets;
  BenchModel b{mesh::generate_organ("liver", o, 4.0 * tets), {}, {}};
  for (int v = 0; v < b.mesh.num_nodes(); ++v)
    if (b.mesh.nodes(v, 2) <= -0.019) b.fixed.push_back(v);
  const int c = nearest_surface_node(b.mesh, Eigen::Vector3d(0.025, 0, 0.045));
  b.op_mask = sphere_with_tets(b.mesh, b.mesh.node(c), op_tets);
  b.center = c;
  return b;
}

}  // namespace softcut::bench
