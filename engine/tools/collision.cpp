#include "tools/collision.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

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

Eigen::Vector3d SurfacePoint::at(const Eigen::MatrixX3d& positions) const {
  return weights(0) * positions.row(nodes[0]).transpose() + weights(1) * positions.row(nodes[1]).transpose() +
         weights(2) * positions.row(nodes[2]).transpose();
}

namespace {

Eigen::Vector3d corner(const ContactSurface& s, int face, int k) {
  return s.positions.row(s.surface.faces(face, k)).transpose();
}

// Barycentric weights of a point q of triangle (a, b, c), clamped to the
// triangle (q comes from closest_point_on_triangle, so only rounding is cut).
Eigen::Vector3d barycentric(const Eigen::Vector3d& q, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c) {
  const Eigen::Vector3d v0 = b - a, v1 = c - a, v2 = q - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double den = d00 * d11 - d01 * d01;
  if (!(den > 0)) return Eigen::Vector3d(1, 0, 0);  // a degenerate face: its first corner
  Eigen::Vector3d w;
  w(1) = (d11 * d20 - d01 * d21) / den;
  w(2) = (d00 * d21 - d01 * d20) / den;
  w(0) = 1 - w(1) - w(2);
  w = w.cwiseMax(0.0);
  return w / w.sum();
}

// Nearest point of the faces `cand` to p: (face, point), face -1 when none.
std::pair<int, Eigen::Vector3d> nearest_on(const ContactSurface& s, const std::vector<int>& cand,
                                           const Eigen::Vector3d& p) {
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_q = p;
  for (int f : cand) {
    const Eigen::Vector3d q = closest_point_on_triangle(p, corner(s, f, 0), corner(s, f, 1), corner(s, f, 2));
    const double d2 = (q - p).squaredNorm();
    if (d2 < best_d2) best_d2 = d2, best = f, best_q = q;
  }
  return {best, best_q};
}

}  // namespace

std::vector<SurfacePoint> surface_patch(const ContactSurface& s, const Eigen::Vector3d& center, double radius,
                                        bool contact_circle) {
  // Faces that may hold a sample: within 2.5 radius of the centre (the
  // nearest point lies within radius of it, a sample within radius of that,
  // and a kept projection within radius / 2 of the sample).
  std::vector<int> cand;
  for (int f = 0; f < s.surface.faces.rows(); ++f) {
    const Eigen::Vector3d a = corner(s, f, 0), b = corner(s, f, 1), c = corner(s, f, 2);
    const Eigen::Vector3d m = (a + b + c) / 3;
    const double reach = 2.5 * radius + std::sqrt(std::max({(a - m).squaredNorm(), (b - m).squaredNorm(), (c - m).squaredNorm()}));
    if ((m - center).squaredNorm() <= (1 + 1e-9) * reach * reach) cand.push_back(f);
  }
  std::vector<SurfacePoint> out;
  const auto [f0, q0] = nearest_on(s, cand, center);
  if (f0 < 0 || (q0 - center).norm() > radius) return out;
  auto add = [&](int f, const Eigen::Vector3d& q, double share) {
    if (!(share > 0)) return;
    SurfacePoint p;
    for (int k = 0; k < 3; ++k) p.nodes[size_t(k)] = s.surface.faces(f, k);
    p.weights = barycentric(q, corner(s, f, 0), corner(s, f, 1), corner(s, f, 2));
    p.share = share;
    out.push_back(p);
  };
  add(f0, q0, 1.0);
  const double disc = contact_circle ? std::sqrt(std::max(0.0, radius * radius - (q0 - center).squaredNorm())) : radius;
  if (!(disc > 0)) return out;  // a sphere just touching: a point
  // The surface's normal at a point of face f: a jaw takes the face's own; a
  // probe the vertex normals interpolated there, the same from either face at
  // an edge (a point on an edge belongs to both, and which one the nearest-
  // point search names must not matter).
  auto normal_at = [&](int f, const Eigen::Vector3d& q) -> Eigen::Vector3d {
    const Eigen::Vector3d a = corner(s, f, 0), b = corner(s, f, 1), c = corner(s, f, 2);
    Eigen::Vector3d m = (b - a).cross(c - a);
    if (contact_circle && m.norm() > 0) {
      const Eigen::Vector3d w = barycentric(q, a, b, c);
      m = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) m += w(k) * s.normals.row(s.surface.faces(f, k)).transpose();
    }
    return m.norm() > 0 ? Eigen::Vector3d(m.normalized()) : Eigen::Vector3d::Zero();
  };
  // Tangent plane at q0.
  const Eigen::Vector3d n = normal_at(f0, q0);
  if (!(n.norm() > 0)) return out;
  const Eigen::Vector3d t1 = n.unitOrthogonal(), t2 = n.cross(t1);
  // A jaw holds what lies under it alike (share 1 inside every bound); a
  // probe's shares fade to 0 at each bound (u: the fraction of it used), so
  // nothing enters or leaves its patch with a finite load.
  auto fade = [&](double u) { return contact_circle ? std::pow(std::max(0.0, 1 - u * u), 2) : (u <= 1 ? 1.0 : 0.0); };
  // Radially a probe presses with Hertz's profile, sqrt(1 - (r / disc)^2)
  // for a sphere on an elastic half-space: zero at the contact's rim.
  auto pressure = [&](double u) { return contact_circle ? std::sqrt(std::max(0.0, 1 - u * u)) : (u <= 1 ? 1.0 : 0.0); };
  // Only surface that faces the jaw as the nearest face does (within 60
  // degrees): not the walls of a cut, nor the back of a thin body.
  auto facing = [&](const Eigen::Vector3d& normal) {
    const double cosine = normal.dot(n);
    if (!contact_circle) return cosine >= 0.5 ? 1.0 : 0.0;
    const double t = std::clamp((cosine - 0.5) / 0.5, 0.0, 1.0);
    return t * t * (3 - 2 * t);
  };
  constexpr double kPi = 3.14159265358979323846;
  for (const auto& [rho, count] : {std::pair{0.5, 6}, std::pair{1.0, 12}})
    for (int k = 0; k < count; ++k) {
      const double th = 2 * kPi * (k + 0.5 * (count == 12)) / count;
      const Eigen::Vector3d x = q0 + rho * disc * (std::cos(th) * t1 + std::sin(th) * t2);
      const auto [f, q] = nearest_on(s, cand, x);
      if (f >= 0)
        add(f, q, fade((q - x).norm() / (0.5 * disc)) * (contact_circle ? pressure((q - q0).norm() / disc) : 1.0) *
                      facing(normal_at(f, q)));
    }
  // And every surface node on the patch: on a mesh finer than the pattern
  // the jaw holds all the tissue under it, not 19 points of it.
  for (int v : s.surface.nodes) {
    const Eigen::Vector3d d = s.positions.row(v).transpose() - q0;
    const double share = pressure(d.norm() / disc) * fade(std::abs(d.dot(n)) / (0.5 * disc)) *
                         facing(s.normals.row(v).transpose());
    if (share > 0) {
      SurfacePoint p;
      p.nodes = {v, v, v};
      p.weights = Eigen::Vector3d(1, 0, 0);
      p.share = share;
      out.push_back(p);
    }
  }
  return out;
}

std::vector<int> point_nodes(const std::vector<SurfacePoint>& points) {
  std::vector<int> nodes;
  for (const SurfacePoint& p : points) nodes.insert(nodes.end(), p.nodes.begin(), p.nodes.end());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

SurfacePoint nearest_surface_point(const Eigen::MatrixX3d& x, const mesh::Surface& surf, const Eigen::Vector3d& p,
                                   const SurfacePoint& prefer, const std::vector<int>& faces) {
  auto shared = [&](int f) {
    int n = 0;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) n += prefer.weights(j) != 0 && surf.faces(f, k) == prefer.nodes[size_t(j)];
    return n;
  };
  int best = -1, best_shared = -1;
  double best_d = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_q = p;
  const int nf = faces.empty() ? int(surf.faces.rows()) : int(faces.size());
  for (int i = 0; i < nf; ++i) {
    const int f = faces.empty() ? i : faces[size_t(i)];
    const Eigen::Vector3d a = x.row(surf.faces(f, 0)), b = x.row(surf.faces(f, 1)), c = x.row(surf.faces(f, 2));
    const Eigen::Vector3d q = closest_point_on_triangle(p, a, b, c);
    const double d = (q - p).norm(), tol = 1e-12 * std::max({(b - a).norm(), (c - a).norm(), 1e-300});
    const int sh = shared(f);
    if (d < best_d - tol || (d <= best_d + tol && sh > best_shared)) best = f, best_d = d, best_q = q, best_shared = sh;
  }
  SurfacePoint out;
  if (best < 0) return prefer;
  out.share = prefer.share;  // the same point of the grip, moved
  for (int k = 0; k < 3; ++k) out.nodes[size_t(k)] = surf.faces(best, k);
  out.weights = barycentric(best_q, x.row(out.nodes[0]).transpose(), x.row(out.nodes[1]).transpose(),
                            x.row(out.nodes[2]).transpose());
  return out;
}

Eigen::Vector3d closest_point_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (!(len2 > 0)) return a;
  return a + std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) * ab;
}

namespace {

// Squared distance between the segments p1-q1 and p2-q2 (Ericson, Real-Time
// Collision Detection §5.1.9).
double segment_segment_distance2(const Eigen::Vector3d& p1, const Eigen::Vector3d& q1, const Eigen::Vector3d& p2,
                                 const Eigen::Vector3d& q2) {
  const Eigen::Vector3d d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a <= 0 && e <= 0) return r.squaredNorm();
  if (a <= 0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) t = 0, s = std::clamp(-c / a, 0.0, 1.0);
      else if (t > 1) t = 1, s = std::clamp((b - c) / a, 0.0, 1.0);
    }
  }
  return ((p1 + s * d1) - (p2 + t * d2)).squaredNorm();
}

// Whether the segment a-b meets the triangle (p, q, r) (both ends on one side
// of its plane: no; else the crossing point inside the triangle).
bool segment_crosses_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& p,
                              const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  const Eigen::Vector3d n = (q - p).cross(r - p);
  const double da = n.dot(a - p), db = n.dot(b - p);
  if ((da > 0 && db > 0) || (da < 0 && db < 0) || da == db) return false;
  const Eigen::Vector3d x = a + da / (da - db) * (b - a);
  return n.dot((q - p).cross(x - p)) >= 0 && n.dot((r - q).cross(x - q)) >= 0 && n.dot((p - r).cross(x - r)) >= 0;
}

}  // namespace

double distance_to_surface(const ContactSurface& s, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  double best2 = std::numeric_limits<double>::infinity();
  for (int f = 0; f < s.surface.faces.rows(); ++f) {
    const Eigen::Vector3d p = corner(s, f, 0), q = corner(s, f, 1), r = corner(s, f, 2);
    // A face whose bounding sphere lies farther than the best so far is skipped.
    const Eigen::Vector3d centre = (p + q + r) / 3;
    const double reach = std::sqrt(std::max({(p - centre).squaredNorm(), (q - centre).squaredNorm(),
                                             (r - centre).squaredNorm()}));
    const double to_centre = (closest_point_on_segment(centre, a, b) - centre).norm() - reach;
    if (to_centre > 0 && to_centre * to_centre > best2) continue;
    double d2 = std::min((closest_point_on_triangle(a, p, q, r) - a).squaredNorm(),
                         (closest_point_on_triangle(b, p, q, r) - b).squaredNorm());
    if (a != b) {
      if (segment_crosses_triangle(a, b, p, q, r)) return 0.0;
      d2 = std::min({d2, segment_segment_distance2(a, b, p, q), segment_segment_distance2(a, b, q, r),
                     segment_segment_distance2(a, b, r, p)});
    }
    best2 = std::min(best2, d2);
  }
  return std::sqrt(best2);
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
