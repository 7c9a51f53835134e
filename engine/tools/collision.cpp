#include "tools/collision.hpp"

#include <algorithm>
#include <cmath>

namespace softcut::tools {

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

std::vector<int> nodes_in_sphere(const ContactSurface& s, const Eigen::Vector3d& center, double radius) {
  std::vector<int> hit;
  const double r2 = radius * radius;
  for (int n : s.surface.nodes)
    if ((s.positions.row(n).transpose() - center).squaredNorm() <= r2) hit.push_back(n);
  if (!hit.empty()) return hit;  // surface.nodes is sorted, so hit is too
  // Tip smaller than the faces: take the nearest face the sphere cuts.
  double best = r2;
  int best_face = -1;
  for (int f = 0; f < s.surface.faces.rows(); ++f) {
    const Eigen::Vector3d a = s.positions.row(s.surface.faces(f, 0)).transpose();
    const Eigen::Vector3d b = s.positions.row(s.surface.faces(f, 1)).transpose();
    const Eigen::Vector3d c = s.positions.row(s.surface.faces(f, 2)).transpose();
    const double d2 = (closest_point_on_triangle(center, a, b, c) - center).squaredNorm();
    if (d2 <= best) best = d2, best_face = f;
  }
  if (best_face < 0) return hit;
  hit = {s.surface.faces(best_face, 0), s.surface.faces(best_face, 1), s.surface.faces(best_face, 2)};
  std::sort(hit.begin(), hit.end());
  return hit;
}

Eigen::Vector3d closest_point_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (!(len2 > 0)) return a;
  return a + std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) * ab;
}

std::vector<int> nodes_near_segment(const ContactSurface& s, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    double radius) {
  std::vector<int> hit;
  const double r2 = radius * radius;
  for (int n : s.surface.nodes) {
    const Eigen::Vector3d x = s.positions.row(n).transpose();
    if ((closest_point_on_segment(x, a, b) - x).squaredNorm() <= r2) hit.push_back(n);
  }
  if (!hit.empty()) return hit;
  // Edge between nodes (faces larger than the radius): the nodes of every
  // face the capsule reaches, from samples along the edge at radius / 2.
  // A face whose bounding sphere lies farther than `radius` from the whole
  // segment cannot be reached by any sample: skipped before sampling (the
  // slack keeps rounding from dropping a face the samples would reach).
  const int samples = 1 + int(std::min(1e4, std::ceil((b - a).norm() / (0.5 * radius))));
  for (int f = 0; f < s.surface.faces.rows(); ++f) {
    const Eigen::Vector3d p = s.positions.row(s.surface.faces(f, 0)).transpose();
    const Eigen::Vector3d q = s.positions.row(s.surface.faces(f, 1)).transpose();
    const Eigen::Vector3d r = s.positions.row(s.surface.faces(f, 2)).transpose();
    const Eigen::Vector3d centre = (p + q + r) / 3;
    const double reach =
        (1 + 1e-9) * (radius + std::sqrt(std::max({(p - centre).squaredNorm(), (q - centre).squaredNorm(),
                                                   (r - centre).squaredNorm()})));
    if ((closest_point_on_segment(centre, a, b) - centre).squaredNorm() > reach * reach) continue;
    for (int k = 0; k <= samples; ++k) {
      const Eigen::Vector3d c = a + (double(k) / samples) * (b - a);
      if ((closest_point_on_triangle(c, p, q, r) - c).squaredNorm() <= r2) {
        for (int j = 0; j < 3; ++j) hit.push_back(s.surface.faces(f, j));
        break;
      }
    }
  }
  std::sort(hit.begin(), hit.end());
  hit.erase(std::unique(hit.begin(), hit.end()), hit.end());
  return hit;
}

}  // namespace softcut::tools
