#include "sim/frame_scene.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>

#include "sim/step.hpp"


namespace softcut::sim {

Eigen::Vector3d shaft_axis(const tools::ToolSpec& spec, const tools::ToolState& ts, const Eigen::Vector3d& up) {
  if (spec.shaft.squaredNorm() > 0) return spec.shaft.normalized();
  if (spec.kind != tools::ToolSpec::Kind::grasper && spec.direction.squaredNorm() > 0)
    return -spec.direction.normalized();
  if (ts.touched && ts.approach.squaredNorm() > 0) return ts.approach;
  const Eigen::Vector3d back = ts.start_tip - ts.tip;
  if (!ts.touched && ts.has_start && back.norm() > spec.radius) return back.normalized();
  return up.normalized();
}

render::SceneContent scene_content(const Model& m, const State& s) {
  const RenderSettings& rs = m.spec.outputs.render;
  render::SceneContent c;
  c.operational = s.cut ? s.cut->operational_tet : m.partition.operational_tet;
  if (s.cut) c.cut_faces = s.cut->cut_face;
  if (rs.show_interface) c.interface_nodes = m.partition.interface;
  if (rs.style == RenderSettings::Style::clinical) {
    // Tissue groups: distinct (E, nu) in order of first use (a few), so each
    // material, a lesion's included, has its colour; split tets keep theirs.
    const std::vector<fem::Material>& mat = s.cut ? s.cut->tet_material : m.tet_material;
    std::vector<std::pair<double, double>> seen;
    c.tet_group.resize(mat.size());
    for (size_t t = 0; t < mat.size(); ++t) {
      const std::pair<double, double> key{mat[t].young, mat[t].poisson};
      auto it = std::find(seen.begin(), seen.end(), key);
      if (it == seen.end()) it = seen.insert(seen.end(), key);
      c.tet_group[t] = int(it - seen.begin());
    }
  }
  if (rs.show_loads) {
    // One arrow per acting load, ending at the centroid of its nodes along
    // its total force; the largest is a tenth of the rest shape's diagonal
    // long, the others in proportion.
    const mesh::TetMesh& mesh = current_mesh(m, s);
    const Eigen::MatrixX3d x = mesh.nodes + s.displacement;
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> at_total;  // (centroid, total force)
    double fmax = 0;
    for (const ActiveLoad& l : s.loads) {
      if (!l.enabled || l.nodes.empty()) continue;
      const double per_node = load_per_node(l, s.time);
      Eigen::Vector3d total = Eigen::Vector3d::Zero(), centroid = Eigen::Vector3d::Zero();
      for (size_t k = 0; k < l.nodes.size(); ++k) {
        total += per_node * l.directions.row(Eigen::Index(k)).transpose();
        centroid += x.row(l.nodes[k]).transpose() / double(l.nodes.size());
      }
      if (!(total.norm() > 0)) continue;  // zero (or not finite: the step reports that)
      at_total.emplace_back(centroid, total);
      fmax = std::max(fmax, total.norm());
    }
    const double scale = 0.1 * (mesh.nodes.colwise().maxCoeff() - mesh.nodes.colwise().minCoeff()).norm() / fmax;
    for (const auto& [tip, f] : at_total) c.arrows.push_back({tip - scale * f, tip});
  }
  for (size_t k = 0; k < s.tools.size() && k < s.tool_specs.size(); ++k) {
    const tools::ToolSpec& spec = s.tool_specs[k];
    const tools::ToolState& ts = s.tools[k];
    // Drawn only while it acts: not before active_from, not after active_until.
    if (!spec.enabled || s.time < spec.active_from || s.time > spec.active_until) continue;
    if (rs.show_forces)
      for (int n : ts.nodes) c.manipulated.push_back({n, ts.tip});
    const Eigen::Vector3d shaft = shaft_axis(spec, ts, rs.up);
    if (spec.kind == tools::ToolSpec::Kind::scalpel) {
      // Blade behind its edge toward the shaft (against the pressing
      // direction when one is given: the blade then lies in the cut plane).
      render::ScalpelShape b;
      b.edge_a = ts.blade_a, b.edge_b = ts.blade_b;
      const double h = std::max(0.25 * spec.blade_length, 2 * spec.radius);
      // The back of the blade: the shaft made normal to the edge. An edge
      // along the shaft (a stab) has no such direction: the blade then stands
      // on any normal to its edge (it is drawn from both sides), not on a line.
      const Eigen::Vector3d edge = ts.blade_b - ts.blade_a;
      Eigen::Vector3d back = shaft;
      if (edge.squaredNorm() > 0) {
        const Eigen::Vector3d e = edge.normalized();
        back = shaft - shaft.dot(e) * e;
        back = back.norm() > 0.1 ? Eigen::Vector3d(back.normalized()) : Eigen::Vector3d(e.unitOrthogonal());
      }
      b.spine = spec.blade_back.squaredNorm() > 0 ? ts.blade_c : Eigen::Vector3d(ts.blade_b + h * back);
      b.handle_end = b.spine + 0.5 * (ts.blade_b - ts.blade_a) + 2.5 * h * shaft;
      b.handle_radius = 0.12 * h;
      c.tools.push_back(b);
    } else if (spec.kind == tools::ToolSpec::Kind::probe) {
      render::ProbeShape p;
      p.tip = ts.tip;
      p.axis = shaft;
      p.radius = spec.radius;
      p.length = 20 * spec.radius;
      c.tools.push_back(p);
    } else {
      render::GrasperShape g;
      g.axis = -shaft;
      g.hinge = g.axis.unitOrthogonal();
      g.jaw_length = 4 * spec.radius;
      g.jaw_width = 1.5 * spec.radius;
      g.shaft_length = 20 * spec.radius;
      // Jaw tips at the tissue they hold (the grip's centroid now), else at the tip.
      Eigen::Vector3d tips = ts.tip;
      if (ts.engaged && !ts.grip.empty()) {
        const Eigen::MatrixX3d x = current_mesh(m, s).nodes + s.displacement;
        tips.setZero();
        for (const tools::SurfacePoint& p : ts.grip) tips += p.at(x);
        tips /= double(ts.grip.size());
      }
      g.pivot = tips - g.axis * g.jaw_length;
      g.opening_deg = ts.engaged ? 0.0 : 30.0;
      c.tools.push_back(g);
    }
  }
  return c;
}

render::RenderSettings render_settings(const Model& m, const State& s) {
  const RenderSettings& r = m.spec.outputs.render;
  render::RenderSettings o;
  o.width = r.width, o.height = r.height;
  o.msaa_samples = r.msaa_samples;
  o.wireframe = r.wireframe;
  o.show_interface = r.show_interface;
  o.show_inclusions = r.show_inclusions;
  o.palette.cut = {float(r.cut_color.x()), float(r.cut_color.y()), float(r.cut_color.z()), 1.0f};
  o.palette.background = {float(r.background.x()), float(r.background.y()), float(r.background.z()), 1.0f};
  o.style = r.style == RenderSettings::Style::paper ? render::Style::paper : render::Style::clinical;
  if (!r.tissue_colors.empty()) {
    o.palette.tissue.clear();
    for (const Eigen::Vector3d& c : r.tissue_colors) o.palette.tissue.push_back({float(c.x()), float(c.y()), float(c.z()), 1.0f});
  }
  o.camera.auto_frame = r.auto_frame;
  o.camera.azimuth_deg = r.azimuth_deg + r.orbit_deg_per_s * s.time;
  o.camera.elevation_deg = r.elevation_deg;
  o.camera.eye = r.eye, o.camera.target = r.target, o.camera.up = r.up;
  o.camera.fov_y_deg = r.fov_deg;
  return o;
}

std::filesystem::path frame_png_path(const std::filesystem::path& dir, int frame) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "frame_%06d.png", frame);
  return dir / "frames" / buf;
}

}  // namespace softcut::sim
