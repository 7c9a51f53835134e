#include "render/tool_geometry.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace softcut::render {
namespace {

constexpr double kPi = std::numbers::pi;

// Unit vectors (u, v) with (u, v, w) right-handed and orthonormal.
void basis(const Eigen::Vector3d& w, Eigen::Vector3d& u, Eigen::Vector3d& v) {
  int axis = 0;
  w.cwiseAbs().minCoeff(&axis);
  u = (Eigen::Vector3d::Unit(axis) - w[axis] * w).normalized();
  v = w.cross(u);
}

Eigen::Vector3d unit(const Eigen::Vector3d& d, const char* what) {
  const double n = d.norm();
  if (!d.allFinite() || !(n > 0.0)) fail(what, " must be a finite, non-zero vector");
  return d / n;
}

void positive(double x, const char* what) {
  if (!(x > 0.0 && std::isfinite(x))) fail(what, " = ", x, " must be positive (m)");
}

// UV sphere, outward counter-clockwise: segments around, segments/2 stacks.
void add_sphere(Triangles& out, const Eigen::Vector3d& c, double r, int segments, const Rgba& color) {
  const int stacks = segments / 2;
  Eigen::Vector3d u, v;
  const Eigen::Vector3d w = Eigen::Vector3d::UnitZ();
  basis(w, u, v);
  auto dir = [&](int k, int j) {
    const double th = kPi * k / stacks, ph = 2.0 * kPi * (j % segments) / segments;
    return Eigen::Vector3d(std::sin(th) * (std::cos(ph) * u + std::sin(ph) * v) + std::cos(th) * w);
  };
  // Quad (a, b, cc, d) of band k; at the poles one of its triangles degenerates and is skipped.
  for (int k = 0; k < stacks; ++k)
    for (int j = 0; j < segments; ++j) {
      const Eigen::Vector3d a = dir(k, j), b = dir(k + 1, j), cc = dir(k + 1, j + 1), d = dir(k, j + 1);
      if (k + 1 < stacks) out.add(c + r * a, c + r * b, c + r * cc, a, b, cc, color);
      if (k > 0) out.add(c + r * a, c + r * cc, c + r * d, a, cc, d, color);
    }
}

// Closed cylinder from `base` along unit `w` for `length`: side (smooth) plus caps (flat).
void add_cylinder(Triangles& out, const Eigen::Vector3d& base, const Eigen::Vector3d& w, double length, double r,
                  int segments, const Rgba& color) {
  Eigen::Vector3d u, v;
  basis(w, u, v);
  const Eigen::Vector3d top = base + length * w;
  for (int j = 0; j < segments; ++j) {
    const double p0 = 2.0 * kPi * j / segments, p1 = 2.0 * kPi * (j + 1) / segments;
    const Eigen::Vector3d n0 = std::cos(p0) * u + std::sin(p0) * v, n1 = std::cos(p1) * u + std::sin(p1) * v;
    const Eigen::Vector3d b0 = base + r * n0, b1 = base + r * n1, t0 = top + r * n0, t1 = top + r * n1;
    out.add(b0, b1, t1, n0, n1, n1, color);
    out.add(b0, t1, t0, n0, n1, n0, color);
    out.add(base, b1, b0, -w, -w, -w, color);
    out.add(top, t0, t1, w, w, w, color);
  }
}

// Box centred at c with right-handed unit axes a[0..2] and half sizes h, outward counter-clockwise.
void add_box(Triangles& out, const Eigen::Vector3d& c, const Eigen::Vector3d (&a)[3], const Eigen::Vector3d& h,
             const Rgba& color) {
  for (int i = 0; i < 3; ++i)
    for (int s : {1, -1}) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      const Eigen::Vector3d fc = c + s * h[i] * a[i], t1 = h[j] * a[j], t2 = h[k] * a[k];
      Eigen::Vector3d q[4] = {fc - t1 - t2, fc + t1 - t2, fc + t1 + t2, fc - t1 + t2};
      if (s < 0) std::swap(q[1], q[3]);
      out.add_flat(q[0], q[1], q[2], color);
      out.add_flat(q[0], q[2], q[3], color);
    }
}

}  // namespace

int sphere_triangles(int segments) { return 2 * segments * (segments / 2 - 1); }
int cylinder_triangles(int segments) { return 4 * segments; }

int add_tool(Triangles& out, const ToolShape& tool, int segments, const Rgba& color) {
  if (segments < 6 || segments % 2) fail("render: tool_segments = ", segments, " must be even and >= 6");
  const int before = out.count();
  if (const auto* p = std::get_if<ProbeShape>(&tool)) {
    positive(p->radius, "probe radius");
    positive(p->length, "probe length");
    if (!p->tip.allFinite()) fail("probe tip is not finite");
    const Eigen::Vector3d w = unit(p->axis, "probe axis");
    add_sphere(out, p->tip, p->radius, segments, color);
    add_cylinder(out, p->tip, w, p->length, 0.5 * p->radius, segments, color);
  } else if (const auto* g = std::get_if<GrasperShape>(&tool)) {
    positive(g->jaw_length, "grasper jaw_length");
    positive(g->jaw_width, "grasper jaw_width");
    positive(g->shaft_length, "grasper shaft_length");
    if (!g->pivot.allFinite() || !std::isfinite(g->opening_deg)) fail("grasper pivot or opening_deg is not finite");
    const Eigen::Vector3d w = unit(g->axis, "grasper axis");
    const Eigen::Vector3d hinge = unit(g->hinge - g->hinge.dot(w) * w, "grasper hinge (normal to the axis)");
    const double half = 0.5 * g->opening_deg * kPi / 180.0;
    for (int side : {1, -1}) {
      const Eigen::Vector3d d = std::cos(half) * w + side * std::sin(half) * hinge.cross(w);
      const Eigen::Vector3d axes[3] = {d, hinge, d.cross(hinge)};
      // Each jaw lies on the side it opens to (axes[2] points to the other
      // jaw), so closed jaws touch along the axis instead of overlapping.
      const Eigen::Vector3d centre = g->pivot + 0.5 * g->jaw_length * d - side * (g->jaw_width / 6.0) * axes[2];
      add_box(out, centre, axes, Eigen::Vector3d(0.5 * g->jaw_length, 0.5 * g->jaw_width, g->jaw_width / 6.0),
              color);
    }
    add_cylinder(out, g->pivot, -w, g->shaft_length, 0.5 * g->jaw_width, segments, color);
  } else if (const auto* s = std::get_if<ScalpelShape>(&tool)) {
    positive(s->handle_radius, "scalpel handle_radius");
    if (!s->edge_a.allFinite() || !s->edge_b.allFinite() || !s->spine.allFinite())
      fail("scalpel blade corners are not finite");
    if ((s->edge_b - s->edge_a).cross(s->spine - s->edge_a).norm() == 0.0)
      fail("scalpel blade is degenerate: edge_a, edge_b and spine are collinear");
    const Eigen::Vector3d w = unit(s->handle_end - s->spine, "scalpel handle (handle_end - spine)");
    out.add_flat(s->edge_a, s->edge_b, s->spine, color);  // both sides, so each is lit from the front
    out.add_flat(s->edge_a, s->spine, s->edge_b, color);
    add_cylinder(out, s->spine, w, (s->handle_end - s->spine).norm(), s->handle_radius, segments, color);
  }
  return out.count() - before;
}

}  // namespace softcut::render
