#include "mesh/quality.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace softcut::mesh {

std::array<double, 6> dihedral_angles_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  // Outward (or all inward) face normals n_k, face k opposite vertex k; the
  // dihedral angle at the edge shared by faces k and l is pi - angle(n_k, n_l).
  const Eigen::Vector3d p[4] = {a, b, c, d};
  Eigen::Vector3d n[4];
  for (int k = 0; k < 4; ++k) {
    const auto& f = kTetFaces[k];
    n[k] = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
    const double len = n[k].norm();
    n[k] = len > 0 ? Eigen::Vector3d(n[k] / len) : Eigen::Vector3d::Constant(std::nan(""));
  }
  // Edge (i, j) is shared by the faces opposite the other two vertices.
  static constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  std::array<double, 6> out{};
  const double vol = signed_volume(a, b, c, d);
  for (int e = 0; e < 6; ++e) {
    int other[2], q = 0;
    for (int v = 0; v < 4; ++v)
      if (v != kEdges[e][0] && v != kEdges[e][1]) other[q++] = v;
    const double cosang = std::clamp(-n[other[0]].dot(n[other[1]]), -1.0, 1.0);
    out[size_t(e)] = vol == 0 ? std::nan("") : std::acos(cosang) * 180 / std::numbers::pi;
  }
  return out;
}

double aspect_ratio(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    const Eigen::Vector3d& d) {
  const double vol = std::abs(signed_volume(a, b, c, d));
  if (!(vol > 0)) return std::numeric_limits<double>::infinity();
  const double area = 0.5 * ((c - b).cross(d - b).norm() + (c - a).cross(d - a).norm() +
                             (b - a).cross(d - a).norm() + (b - a).cross(c - a).norm());
  const double r = 3 * vol / area;
  const Eigen::Vector3d u = b - a, v = c - a, w = d - a;
  const double R = (u.squaredNorm() * v.cross(w) + v.squaredNorm() * w.cross(u) + w.squaredNorm() * u.cross(v))
                       .norm() / (12 * vol);
  return R / (3 * r);
}

QualityStats tet_quality(const TetMesh& m, const QualityThresholds& th) {
  QualityStats s;
  s.num_tets = m.num_tets();
  if (s.num_tets == 0) return s;
  const double inf = std::numeric_limits<double>::infinity();
  s.min_volume = s.min_dihedral_deg = s.min_aspect = s.min_edge = inf;
  s.max_volume = s.max_dihedral_deg = s.max_aspect = s.max_edge = -inf;
  double aspect_sum = 0;
  for (int t = 0; t < s.num_tets; ++t) {
    const Eigen::Vector3d p[4] = {m.node(m.tets(t, 0)), m.node(m.tets(t, 1)), m.node(m.tets(t, 2)),
                                  m.node(m.tets(t, 3))};
    const double vol = signed_volume(p[0], p[1], p[2], p[3]);
    s.min_volume = std::min(s.min_volume, vol);
    s.max_volume = std::max(s.max_volume, vol);
    s.total_volume += vol;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const double l = (p[i] - p[j]).norm();
        s.min_edge = std::min(s.min_edge, l);
        s.max_edge = std::max(s.max_edge, l);
      }
    const double asp = aspect_ratio(p[0], p[1], p[2], p[3]);
    const auto ang = dihedral_angles_deg(p[0], p[1], p[2], p[3]);
    const bool flat = !(vol > 0);
    double lo = inf, hi = -inf;
    for (double x : ang) lo = std::min(lo, x), hi = std::max(hi, x);
    if (flat) lo = 0, hi = 180;  // degenerate or inverted: count as the worst angles
    s.min_dihedral_deg = std::min(s.min_dihedral_deg, lo);
    s.max_dihedral_deg = std::max(s.max_dihedral_deg, hi);
    if (asp > s.max_aspect || s.worst_tet < 0) s.worst_tet = t;
    s.min_aspect = std::min(s.min_aspect, asp);
    s.max_aspect = std::max(s.max_aspect, asp);
    aspect_sum += asp;
    const bool small = lo < th.min_dihedral_deg, large = hi > th.max_dihedral_deg, high = asp > th.max_aspect;
    s.num_nonpositive += flat;
    s.num_small_dihedral += small;
    s.num_large_dihedral += large;
    s.num_high_aspect += high;
    s.num_poor += flat || small || large || high;
  }
  s.mean_aspect = aspect_sum / s.num_tets;
  return s;
}

}  // namespace softcut::mesh
