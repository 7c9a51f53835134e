#include "tools/tool.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "core/error.hpp"
#include "core/printable.hpp"
#include "core/suggest.hpp"

namespace softcut::tools {

namespace {

std::string tool_label(const ToolSpec& t, const std::string& where) {
  std::string s = where.empty() ? t.where : where;
  return cat(s.empty() ? "" : s + ": ", "tool '", t.name, "'");
}

}  // namespace

void check_tool(const ToolSpec& t, const std::string& where) {
  const std::string w = tool_label(t, where);
  if (!(t.radius > 0) || !std::isfinite(t.radius)) fail(w, ": radius must be > 0 m, got ", t.radius);
  check_path(t.path, w + " path");
  if (!t.direction.allFinite()) fail(w, ": direction must be finite");
  if (!t.shaft.allFinite()) fail(w, ": shaft must be finite");
  if (!(t.stop >= t.start) || std::isnan(t.start))
    fail(w, ": stop (", t.stop, " s) must not be before start (", t.start, " s)");
  if (t.kind == ToolSpec::Kind::scalpel) {
    if (!(t.blade_length > 0) || !std::isfinite(t.blade_length))
      fail(w, ": blade_length must be > 0 m, got ", t.blade_length);
    if (!t.blade_axis.allFinite() || !(t.blade_axis.norm() > 0)) fail(w, ": blade axis must be a nonzero vector");
    if (!(t.cut_pressure > 0)) fail(w, ": cut_pressure must be > 0 Pa, got ", t.cut_pressure);
    if (!t.blade_back.allFinite()) fail(w, ": blade back must be finite");
    if (t.blade_back.squaredNorm() > 0 && t.blade_back.cross(t.blade_axis).norm() <= 1e-9 * t.blade_back.norm() * t.blade_axis.norm())
      fail(w, ": blade back must not lie along the edge (the blade triangle would be flat)");
  }
  if (t.drive == ToolSpec::Drive::force) {
    check_ramp(t.force, w + " force");
  } else if (!(t.stiffness > 0) || !std::isfinite(t.stiffness)) {
    fail(w, ": a spring tool needs stiffness > 0 N/m, got ", t.stiffness);
  }
}

void blade_edge(const ToolSpec& spec, const Eigen::Vector3d& center, Eigen::Vector3d& a, Eigen::Vector3d& b) {
  const Eigen::Vector3d half = 0.5 * spec.blade_length * spec.blade_axis.normalized();
  a = center - half;
  b = center + half;
}

void update_tool(const ToolSpec& spec, ToolState& st, double t, const ContactSurface& s) {
  if (!st.override_tip) st.tip = evaluate(spec.path, t);
  st.forces.clear();
  st.total_force.setZero();
  const bool scalpel = spec.kind == ToolSpec::Kind::scalpel;
  if (scalpel) {
    st.has_prev = st.has_prev || st.blade_a != st.blade_b;  // a previous frame set the edge
    st.prev_a = st.blade_a, st.prev_b = st.blade_b, st.prev_c = st.blade_c;
    blade_edge(spec, st.tip, st.blade_a, st.blade_b);
    st.blade_c = st.tip + spec.blade_back;
    st.pressure = 0.0;
    st.cutting = false;
  }
  const bool active = spec.enabled && t >= spec.start && t <= spec.stop;
  if (!active) {
    st.engaged = false;
    st.nodes.clear();
    st.grip.clear();
    st.offsets.clear();
    return;
  }
  // Scalpel contact: nodes within `radius` of the edge. A blade that moves
  // more than its radius in a frame can pass the surface between two frames
  // touching it on neither, so the poses in between are asked too (steps of
  // at most a radius, from last frame's): the first that touches is the
  // contact, and the spring drive pushes from there. Not within a cut (the
  // tissue yields there, and a blade lifted out must not touch again).
  Eigen::Vector3d contact_a = st.blade_a, contact_b = st.blade_b;
  if (scalpel) {
    st.nodes = nodes_near_segment(s, st.blade_a, st.blade_b, spec.radius);
    if (st.nodes.empty() && st.has_prev && !st.in_cut) {
      const double travel = std::max((st.blade_a - st.prev_a).norm(), (st.blade_b - st.prev_b).norm());
      const int steps = int(std::min(256.0, std::ceil(travel / spec.radius)));
      for (int i = 1; i < steps && st.nodes.empty(); ++i) {
        const double f = double(i) / steps;
        contact_a = st.prev_a + f * (st.blade_a - st.prev_a);
        contact_b = st.prev_b + f * (st.blade_b - st.prev_b);
        st.nodes = nodes_near_segment(s, contact_a, contact_b, spec.radius);
      }
    }
    st.engaged = !st.nodes.empty();
  } else if (spec.kind == ToolSpec::Kind::probe && spec.drive == ToolSpec::Drive::spring) {
    st.nodes = nodes_in_sphere(s, st.tip, spec.radius);  // re-detected every frame; a penalty per node
    st.engaged = !st.nodes.empty();
  } else if (spec.kind == ToolSpec::Kind::probe || !st.engaged) {
    // A force-driven probe presses over its contact area, re-detected every
    // frame; a grasper closes on first contact, on the patch under its jaw.
    const bool probe = spec.kind == ToolSpec::Kind::probe;
    st.grip = surface_patch(s, st.tip, spec.radius, probe);
    st.engaged = !st.grip.empty();
    st.nodes = point_nodes(st.grip);
    st.offsets.clear();
    for (const SurfacePoint& p : st.grip) st.offsets.push_back(p.at(s.positions) - st.tip);
  }
  if (!st.has_start) st.start_tip = st.tip, st.has_start = true;
  st.was_active = true;
  if (!st.engaged && !st.touched) {
    const double gap = std::max(0.0, (scalpel ? distance_to_surface(s, st.blade_a, st.blade_b)
                                              : distance_to_surface(s, st.tip, st.tip)) - spec.radius);
    if (gap < st.closest_gap) st.closest_gap = gap, st.closest_time = t;
  }
  if (st.engaged && !st.touched) {
    st.touched = true;
    const Eigen::Vector3d back = st.start_tip - st.tip;
    st.approach = back.norm() > spec.radius ? Eigen::Vector3d(back.normalized()) : Eigen::Vector3d::Zero();
  }
  const size_t k = st.nodes.size();
  if (k == 0) return;
  st.forces.assign(k, Eigen::Vector3d::Zero());
  if (!st.grip.empty()) {
    // Grasper, force-driven probe: per grip point by its share, then onto
    // its nodes by its weights.
    const size_t np = st.grip.size();
    double shares = 0;
    for (const SurfacePoint& p : st.grip) shares += p.share;
    Eigen::Vector3d dir = spec.direction;
    if (spec.drive == ToolSpec::Drive::force && dir.squaredNorm() == 0) {
      if (spec.kind == ToolSpec::Kind::probe) {  // against the surface's normal there
        for (const SurfacePoint& p : st.grip) dir -= p.share * p.at(s.normals);
      } else {  // toward the tip from the grip's centroid
        Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
        for (const SurfacePoint& p : st.grip) centroid += p.at(s.positions);
        dir = st.tip - centroid / double(np);
      }
    }
    const double f = spec.drive == ToolSpec::Drive::force ? evaluate(spec.force, t) / shares : 0.0;
    const double kp = spec.stiffness / shares;
    for (size_t i = 0; i < np; ++i) {
      const SurfacePoint& p = st.grip[i];
      Eigen::Vector3d fp = Eigen::Vector3d::Zero();
      if (spec.drive == ToolSpec::Drive::spring) fp = p.share * kp * (st.tip + st.offsets[i] - p.at(s.positions));
      else if (dir.norm() > 0) fp = p.share * f * dir.normalized();  // no defined direction (tip at the centroid): none
      for (int j = 0; j < 3; ++j) {
        const size_t at = size_t(std::lower_bound(st.nodes.begin(), st.nodes.end(), p.nodes[size_t(j)]) - st.nodes.begin());
        st.forces[at] += p.weights(j) * fp;
      }
    }
  } else if (spec.drive == ToolSpec::Drive::force) {
    Eigen::Vector3d dir = spec.direction;
    if (dir.squaredNorm() == 0)
      for (int n : st.nodes) dir -= s.normals.row(n).transpose();
    const double len = dir.norm();
    if (!(len > 0)) return;  // no defined direction (normals that cancel): no force
    const Eigen::Vector3d per_node = evaluate(spec.force, t) / double(k) * dir / len;
    for (size_t i = 0; i < k; ++i) st.forces[i] = per_node;
  } else {
    const double kn = spec.stiffness / double(k);
    for (size_t i = 0; i < k; ++i) {  // probe / scalpel: penalty pushing the node out of the sphere / capsule
      const Eigen::Vector3d x = s.positions.row(st.nodes[i]).transpose();
      const Eigen::Vector3d d = x - (scalpel ? closest_point_on_segment(x, contact_a, contact_b) : st.tip);
      const double dn = d.norm();
      Eigen::Vector3d out = dn > 0 ? Eigen::Vector3d(d / dn) : Eigen::Vector3d(s.normals.row(st.nodes[i]).transpose());
      st.forces[i] = kn * std::max(0.0, spec.radius - dn) * out;
    }
  }
  for (const auto& f : st.forces) st.total_force += f;
  if (scalpel) {
    st.pressure = st.total_force.norm() / (spec.blade_length * 2.0 * spec.radius);
    st.touch_pressure = st.pressure, st.touch_time = t;
    if (st.pressure > st.max_pressure || st.max_pressure_time < 0) st.max_pressure = st.pressure, st.max_pressure_time = t;
  }
}

void rebind_grip(ToolState& st, const Eigen::MatrixX3d& x, const mesh::Surface& surf) {
  if (st.grip.empty()) return;
  // Faces near the grip: within its extent plus each face's size.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  std::vector<Eigen::Vector3d> at;
  for (const SurfacePoint& p : st.grip) {
    at.push_back(p.at(x));
    lo = lo.cwiseMin(at.back()), hi = hi.cwiseMax(at.back());
  }
  std::vector<int> faces;
  for (int f = 0; f < surf.faces.rows(); ++f) {
    Eigen::Vector3d flo = x.row(surf.faces(f, 0)).transpose(), fhi = flo;
    for (int k = 1; k < 3; ++k) flo = flo.cwiseMin(x.row(surf.faces(f, k)).transpose()), fhi = fhi.cwiseMax(x.row(surf.faces(f, k)).transpose());
    const double slack = (fhi - flo).norm() + 1e-12;
    if (((flo.array() - slack) <= hi.array()).all() && ((fhi.array() + slack) >= lo.array()).all()) faces.push_back(f);
  }
  for (size_t i = 0; i < st.grip.size(); ++i) st.grip[i] = nearest_surface_point(x, surf, at[i], st.grip[i], faces);
  st.nodes = point_nodes(st.grip);
  st.forces.assign(st.nodes.size(), Eigen::Vector3d::Zero());
}

bool is_implicit_spring(const ToolSpec& spec) {
  return spec.kind == ToolSpec::Kind::grasper && spec.drive == ToolSpec::Drive::spring && spec.implicit;
}

const char* to_string(ToolSpec::Kind k) {
  switch (k) {
    case ToolSpec::Kind::probe: return "probe";
    case ToolSpec::Kind::grasper: return "grasper";
    case ToolSpec::Kind::scalpel: return "scalpel";
  }
  return "?";
}
const char* to_string(ToolSpec::Drive d) { return d == ToolSpec::Drive::force ? "force" : "spring"; }

ToolSpec::Kind parse_tool_kind(std::string_view text) {
  if (text == "probe") return ToolSpec::Kind::probe;
  if (text == "grasper") return ToolSpec::Kind::grasper;
  if (text == "scalpel") return ToolSpec::Kind::scalpel;
  fail("tool: unknown kind '", printable(text), "'", suggest(text, {"probe", "grasper", "scalpel"}));
}

ToolSpec::Drive parse_drive(std::string_view text) {
  if (text == "force") return ToolSpec::Drive::force;
  if (text == "spring") return ToolSpec::Drive::spring;
  fail("tool: unknown drive '", printable(text), "'", suggest(text, {"force", "spring"}));
}

}  // namespace softcut::tools
