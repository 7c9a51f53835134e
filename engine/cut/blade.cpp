#include "cut/blade.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace softcut::cut {

namespace {

// Relative tolerance of the inside-triangle test: a crossing on the shared
// diagonal of a quad, or on the edge between two consecutive steps, is found
// by at least one triangle.
constexpr double kInsideEps = 1e-9;

bool degenerate(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  const double scale = std::max({(q - p).squaredNorm(), (r - p).squaredNorm(), (r - q).squaredNorm()});
  return !(scale > 0) || (q - p).cross(r - p).squaredNorm() <= 1e-24 * scale * scale;
}

void push(SweptSurface& s, const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  if (!p.allFinite() || !q.allFinite() || !r.allFinite())
    fail("blade: a pose has a non-finite coordinate (", p.transpose(), " / ", q.transpose(), " / ", r.transpose(),
         "); check the scalpel path");
  if (degenerate(p, q, r)) return;
  Eigen::Matrix3d t;
  t.col(0) = p;
  t.col(1) = q;
  t.col(2) = r;
  s.triangles.push_back(t);
}

Eigen::Vector3d unit_normal(const Eigen::Matrix3d& t) {
  return (t.col(1) - t.col(0)).cross(t.col(2) - t.col(0)).normalized();
}

}  // namespace

SweptSurface sweep_segment(const Eigen::Vector3d& a0, const Eigen::Vector3d& b0,
                           const Eigen::Vector3d& a1, const Eigen::Vector3d& b1) {
  SweptSurface s;
  push(s, a0, b0, b1);
  push(s, a0, b1, a1);
  return s;
}

SweptSurface sweep_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  SweptSurface s;
  push(s, p, q, r);
  return s;
}

void append(SweptSurface& s, const SweptSurface& more) {
  s.triangles.insert(s.triangles.end(), more.triangles.begin(), more.triangles.end());
}

void bounds(const SweptSurface& s, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  lo.setConstant(std::numeric_limits<double>::infinity());
  hi.setConstant(-std::numeric_limits<double>::infinity());
  for (const auto& t : s.triangles) {
    lo = lo.cwiseMin(t.rowwise().minCoeff());
    hi = hi.cwiseMax(t.rowwise().maxCoeff());
  }
}

double segment_crossing(const SweptSurface& s, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        Eigen::Vector3d* n_out) {
  const double len = (b - a).norm();
  if (!(len > 0)) return -1;
  for (const auto& tri : s.triangles) {
    const Eigen::Vector3d n = unit_normal(tri);
    const double da = n.dot(a - tri.col(0)), db = n.dot(b - tri.col(0));
    const double flat = 1e-12 * len;
    if (std::abs(da) <= flat && std::abs(db) <= flat) continue;  // in the plane
    if ((da > flat && db > flat) || (da < -flat && db < -flat)) continue;
    const double t = std::clamp(da / (da - db), 0.0, 1.0);
    const Eigen::Vector3d p = a + t * (b - a);
    // Barycentric coordinates of p in the triangle (p lies in its plane).
    const Eigen::Vector3d e0 = tri.col(1) - tri.col(0), e1 = tri.col(2) - tri.col(0), w = p - tri.col(0);
    const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1);
    const double d20 = w.dot(e0), d21 = w.dot(e1);
    const double den = d00 * d11 - d01 * d01;
    const double v = (d11 * d20 - d01 * d21) / den, u = (d00 * d21 - d01 * d20) / den;
    if (v >= -kInsideEps && u >= -kInsideEps && v + u <= 1 + kInsideEps) {
      if (n_out) *n_out = n;
      return t;
    }
  }
  return -1;
}

double point_triangle_distance(const Eigen::Vector3d& x, const Eigen::Matrix3d& tri) {
  // Closest point on a triangle by Voronoi regions of its vertices and edges.
  const Eigen::Vector3d a = tri.col(0), b = tri.col(1), c = tri.col(2);
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = x - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();
  const Eigen::Vector3d bp = x - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (x - (a + d1 / (d1 - d3) * ab)).norm();
  const Eigen::Vector3d cp = x - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (x - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (x - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double den = 1 / (va + vb + vc);
  return (x - (a + ab * (vb * den) + ac * (vc * den))).norm();
}

double distance(const SweptSurface& s, const Eigen::Vector3d& x, Eigen::Vector3d* n_out) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& tri : s.triangles) {
    const double d = point_triangle_distance(x, tri);
    if (d < best) {
      best = d;
      if (n_out) *n_out = unit_normal(tri);
    }
  }
  return best;
}

}  // namespace softcut::cut
