#include "sim/frame_scene.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>

#include "core/error.hpp"
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
  // Markers go into every scene (a re-render may show them); the settings
  // say which are drawn.
  c.interface_nodes = m.partition.interface;
  // Tissue groups: the s:material call that set each tet's material (split
  // tets keep their parent's), for the colours and the label image.
  const std::vector<fem::Material>& mat = s.cut ? s.cut->tet_material : m.tet_material;
  c.tet_group.resize(mat.size());
  for (size_t t = 0; t < mat.size(); ++t)
    c.tet_group[t] = m.tet_group[size_t(s.cut ? s.cut->origin_tet[t] : int(t))];
  const LabelLegend legend = label_legend(m);
  c.group_labels = legend.group;
  c.cut_label = legend.cut;
  {
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
    // Drawn only while it acts: not before start, not after stop.
    if (!spec.enabled || s.time < spec.start || s.time > spec.stop) continue;
    c.tool_labels.push_back(k < legend.tool.size() ? legend.tool[k] : 0);
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

std::vector<Eigen::Vector3d> tissue_palette(const ScenarioSpec& spec) {
  // The engine's default palette (parenchyma red-brown, a pale lesion tone, ...).
  const render::Palette defaults;
  const std::vector<Eigen::Vector3d>& given = spec.outputs.render.tissue_colors;
  std::vector<Eigen::Vector3d> out;
  for (size_t g = 0; g <= spec.materials.size(); ++g) {
    if (g < spec.materials.size() && spec.materials[g].has_color) {
      out.push_back(spec.materials[g].color);
    } else if (!given.empty()) {
      out.push_back(given[g % given.size()]);
    } else {
      const render::Rgba& d = defaults.tissue[g % defaults.tissue.size()];
      out.emplace_back(d[0], d[1], d[2]);
    }
  }
  return out;
}

render::RenderSettings render_settings(const RenderSettings& r, const std::vector<Eigen::Vector3d>& palette,
                                       const render::CameraSettings& camera) {
  render::RenderSettings o;
  o.width = r.width, o.height = r.height;
  o.msaa_samples = r.msaa_samples;
  o.wireframe = r.wireframe;
  o.show_interface = r.show_interface;
  o.show_forces = r.show_forces;
  o.show_loads = r.show_loads;
  o.show_inclusions = r.show_inclusions;
  o.palette.cut = {float(r.cut_color.x()), float(r.cut_color.y()), float(r.cut_color.z()), 1.0f};
  o.palette.background = {float(r.background.x()), float(r.background.y()), float(r.background.z()), 1.0f};
  o.style = r.style == RenderSettings::Style::paper ? render::Style::paper : render::Style::clinical;
  if (!palette.empty()) {
    o.palette.tissue.clear();
    for (const Eigen::Vector3d& c : palette) o.palette.tissue.push_back({float(c.x()), float(c.y()), float(c.z()), 1.0f});
  }
  o.camera = camera;
  return o;
}

render::CameraSettings camera_settings(const Model& m, const State& s) {
  const RenderSettings& r = m.spec.outputs.render;
  const CameraSpec& c = m.spec.outputs.camera;
  render::CameraSettings o;
  o.auto_frame = r.auto_frame;
  o.azimuth_deg = r.azimuth_deg + r.orbit_deg_per_s * s.time;
  o.elevation_deg = r.elevation_deg;
  o.eye = r.eye, o.target = r.target, o.up = r.up;
  o.fov_y_deg = r.fov_deg;
  if (c.kind == CameraSpec::Kind::none) return o;
  o.auto_frame = false;
  o.up = c.up;
  if (c.fov_deg > 0) o.fov_y_deg = c.fov_deg;
  if (c.kind == CameraSpec::Kind::path) {
    o.eye = tools::evaluate(c.eye, s.time);
    o.target = c.target_moves ? tools::evaluate(c.target_path, s.time) : c.target;
    return o;
  }
  // An endoscope on the tool's port: behind its tip along its shaft, a
  // little off the axis toward `up` (so the instrument shows), looking at
  // the tip (or `lead` beyond it).
  for (size_t k = 0; k < s.tool_specs.size() && k < s.tools.size(); ++k) {
    if (s.tool_specs[k].name != c.follow) continue;
    const tools::ToolState& ts = s.tools[k];
    const Eigen::Vector3d tip = ts.tip, shaft = shaft_axis(s.tool_specs[k], ts, c.up);
    Eigen::Vector3d side = c.up - c.up.dot(shaft) * shaft;
    side = side.norm() > 1e-9 ? Eigen::Vector3d(side.normalized()) : Eigen::Vector3d(shaft.unitOrthogonal());
    o.eye = tip + c.distance * shaft + c.offset * side;
    o.target = tip - c.lead * shaft;
    return o;
  }
  fail(c.where.empty() ? "" : c.where + ": ", "camera: follows tool '", c.follow, "', which the run does not have");
}

render::RenderSettings render_settings(const Model& m, const State& s) {
  return render_settings(m.spec.outputs.render, tissue_palette(m.spec), camera_settings(m, s));
}

LabelLegend label_legend(const Model& m) {
  LabelLegend l;
  std::uint32_t next = 1;
  auto add = [&](std::string name, const char* kind) {
    l.entries.push_back({next, std::move(name), kind});
    return next++;
  };
  for (const MaterialAssignment& a : m.spec.materials)
    l.group.push_back(add(a.preset.empty() ? a.name : a.name + " (" + a.preset + ")", "tissue"));
  // Tets no s:material call covers have the default material.
  const bool uncovered = std::find(m.tet_group.begin(), m.tet_group.end(), int(m.spec.materials.size())) != m.tet_group.end();
  l.group.push_back(uncovered ? add("default material", "tissue") : 0);
  l.cut = add("cut surface", "cut");
  for (const tools::ToolSpec& t : m.spec.tools) l.tool.push_back(add(t.name, tools::to_string(t.kind)));
  return l;
}

std::filesystem::path frame_png_path(const std::filesystem::path& dir, int frame) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "frame_%06d.png", frame);
  return dir / "frames" / buf;
}

}  // namespace softcut::sim
