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

// A closed hexahedron from its 8 corners: c[0..3] one end's face, c[4..7]
// the other end's, both counter-clockwise seen from the first end's outside
// (flat shading, 12 triangles).
void add_hexahedron(Triangles& out, const Eigen::Vector3d (&c)[8], const Rgba& color) {
  const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  for (const auto& f : faces) {
    out.add_flat(c[f[0]], c[f[1]], c[f[2]], color);
    out.add_flat(c[f[0]], c[f[2]], c[f[3]], color);
  }
}

}  // namespace

int sphere_triangles(int segments) { return 2 * segments * (segments / 2 - 1); }
int cylinder_triangles(int segments) { return 4 * segments; }

int add_tool(Triangles& out, const ToolShape& tool, int segments, const Rgba& color) {
  return add_tool(out, tool, segments, color, color);
}

int add_tool(Triangles& out, const ToolShape& tool, int segments, const Rgba& steel, const Rgba& dark) {
  if (segments < 6 || segments % 2) fail("render: tool_segments = ", segments, " must be even and >= 6");
  const int before = out.count();
  if (const auto* p = std::get_if<ProbeShape>(&tool)) {
    positive(p->radius, "probe radius");
    positive(p->length, "probe length");
    if (!p->tip.allFinite()) fail("probe tip is not finite");
    const Eigen::Vector3d w = unit(p->axis, "probe axis");
    add_sphere(out, p->tip, p->radius, segments, steel);
    add_cylinder(out, p->tip, w, p->length, 0.5 * p->radius, segments, dark);
  } else if (const auto* g = std::get_if<GrasperShape>(&tool)) {
    positive(g->jaw_length, "grasper jaw_length");
    positive(g->jaw_width, "grasper jaw_width");
    positive(g->shaft_length, "grasper shaft_length");
    if (!g->pivot.allFinite() || !std::isfinite(g->opening_deg)) fail("grasper pivot or opening_deg is not finite");
    const Eigen::Vector3d w = unit(g->axis, "grasper axis");
    const Eigen::Vector3d hinge = unit(g->hinge - g->hinge.dot(w) * w, "grasper hinge (normal to the axis)");
    const double half = 0.5 * g->opening_deg * kPi / 180.0, thick = g->jaw_width / 3.0;
    for (int side : {1, -1}) {
      const Eigen::Vector3d d = std::cos(half) * w + side * std::sin(half) * hinge.cross(w);
      // Each jaw lies on the side it opens to (`out` points away from the
      // other jaw), so closed jaws touch along the axis instead of overlapping.
      const Eigen::Vector3d out_dir = side * d.cross(hinge).normalized() * -1.0;
      const Eigen::Vector3d base = g->pivot, tip = g->pivot + g->jaw_length * d;
      const double wb = 0.5 * g->jaw_width, wt = 0.25 * g->jaw_width;
      Eigen::Vector3d c[8] = {base - wb * hinge, base + wb * hinge, base + wb * hinge + thick * out_dir,
                              base - wb * hinge + thick * out_dir, tip - wt * hinge, tip + wt * hinge,
                              tip + wt * hinge + thick * out_dir, tip - wt * hinge + thick * out_dir};
      // Outward: the base face's winding must face away from the tip.
      if ((c[1] - c[0]).cross(c[3] - c[0]).dot(d) < 0) {
        std::swap(c[1], c[3]);
        std::swap(c[5], c[7]);
      }
      add_hexahedron(out, c, steel);
    }
    // The clevis: a short cylinder across the hinge at the pivot.
    add_cylinder(out, g->pivot - 0.5 * g->jaw_width * hinge, hinge, g->jaw_width, 0.5 * g->jaw_width, segments, steel);
    add_cylinder(out, g->pivot, -w, g->shaft_length, 0.5 * g->jaw_width, segments, dark);
  } else if (const auto* s = std::get_if<ScalpelShape>(&tool)) {
    positive(s->handle_radius, "scalpel handle_radius");
    if (!s->edge_a.allFinite() || !s->edge_b.allFinite() || !s->spine.allFinite())
      fail("scalpel blade corners are not finite");
    const Eigen::Vector3d plane = (s->edge_b - s->edge_a).cross(s->spine - s->edge_a);
    if (plane.norm() == 0.0) fail("scalpel blade is degenerate: edge_a, edge_b and spine are collinear");
    const Eigen::Vector3d w = unit(s->handle_end - s->spine, "scalpel handle (handle_end - spine)");
    // The blade: a thin tetrahedron, sharp along the edge, its spine
    // thickened across the blade's plane.
    const Eigen::Vector3d n = plane.normalized();
    const double th = 0.5 * s->handle_radius;
    const Eigen::Vector3d sp = s->spine + 0.5 * th * n, sm = s->spine - 0.5 * th * n;
    out.add_flat(s->edge_a, s->edge_b, sp, steel);
    out.add_flat(s->edge_b, s->edge_a, sm, steel);
    out.add_flat(s->edge_a, sp, sm, steel);
    out.add_flat(s->edge_b, sm, sp, steel);
    // The handle: a flat bar, wide in the blade's plane.
    const Eigen::Vector3d across = (n.cross(w)).norm() > 1e-9 ? Eigen::Vector3d(n.cross(w).normalized())
                                                               : Eigen::Vector3d(w.unitOrthogonal());
    const Eigen::Vector3d thick_dir = w.cross(across);
    const double len = (s->handle_end - s->spine).norm(), hw = 1.5 * s->handle_radius, ht = 0.6 * s->handle_radius;
    const Eigen::Vector3d axes[3] = {w, across, thick_dir};
    add_box(out, s->spine + 0.5 * len * w, axes, Eigen::Vector3d(0.5 * len, hw, ht), dark);
  }
  return out.count() - before;
}

}  // namespace softcut::render
