#include "cut/tet_quality.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace softcut::cut {

double min_dihedral_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                        const Eigen::Vector3d& d) {
  const Eigen::Vector3d x[4] = {a, b, c, d};
  // Area vectors of the faces opposite each vertex (orientation-consistent).
  Eigen::Vector3d n[4];
  for (int f = 0; f < 4; ++f) {
    const int* v = mesh::kTetFaces[f];
    n[f] = (x[v[1]] - x[v[0]]).cross(x[v[2]] - x[v[0]]);
    const double len = n[f].norm();
    if (!(len > 0)) return 0;
    n[f] /= len;
  }
  if (mesh::signed_volume(a, b, c, d) == 0) return 0;
  // Interior dihedral at the edge shared by faces i and j has cosine
  // -n_i . n_j; the smallest angle has the largest cosine (one acos).
  double max_cos = -1;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) max_cos = std::max(max_cos, -n[i].dot(n[j]));
  return std::acos(std::clamp(max_cos, -1.0, 1.0)) * 180 / std::numbers::pi;
}

double min_dihedral_deg(const mesh::TetMesh& m, int t) {
  return min_dihedral_deg(m.node(m.tets(t, 0)), m.node(m.tets(t, 1)), m.node(m.tets(t, 2)),
                          m.node(m.tets(t, 3)));
}

double volume_length_ratio(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                           const Eigen::Vector3d& d) {
  const double l2 = ((b - a).squaredNorm() + (c - a).squaredNorm() + (d - a).squaredNorm() +
                     (c - b).squaredNorm() + (d - b).squaredNorm() + (d - c).squaredNorm()) / 6;
  if (!(l2 > 0)) return 0;
  return 6 * std::sqrt(2.0) * mesh::signed_volume(a, b, c, d) / (l2 * std::sqrt(l2));
}

double volume_length_ratio(const mesh::TetMesh& m, int t) {
  return volume_length_ratio(m.node(m.tets(t, 0)), m.node(m.tets(t, 1)), m.node(m.tets(t, 2)),
                             m.node(m.tets(t, 3)));
}

}  // namespace softcut::cut
