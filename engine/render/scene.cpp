#include "render/scene.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include "mesh/surface.hpp"

namespace softcut::render {
namespace {

void check_settings(const RenderSettings& s) {
  if (s.width < 1 || s.height < 1 || s.width > 16384 || s.height > 16384)
    fail("render: image size ", s.width, " x ", s.height, " must be between 1 and 16384 pixels per side");
  if (s.msaa_samples < 0 || s.msaa_samples > 64) fail("render: msaa_samples = ", s.msaa_samples, " must be 0..64");
  if (!(s.crease_angle_deg >= 0.0 && s.crease_angle_deg <= 180.0))
    fail("render: crease_angle_deg = ", s.crease_angle_deg, " must lie in [0, 180]");
  if (!(s.point_size_px > 0 && s.line_width_px > 0 && s.wire_width_px > 0))
    fail("render: point_size_px, line_width_px and wire_width_px must be positive");
  if (s.style == Style::clinical && s.palette.tissue.empty())
    fail("render: the clinical style needs at least one tissue colour in the palette");
  if (!(s.palette.cut_tint >= 0.0f && s.palette.cut_tint <= 1.0f))
    fail("render: palette cut_tint = ", s.palette.cut_tint, " must lie in [0, 1]");
  if (!(s.palette.inclusion_alpha > 0.0f && s.palette.inclusion_alpha <= 1.0f))
    fail("render: palette inclusion_alpha = ", s.palette.inclusion_alpha, " must lie in (0, 1]");
}

void check_content(const mesh::TetMesh& m, const Eigen::MatrixX3d& x, const SceneContent& c) {
  const int nnode = m.num_nodes(), ntet = m.num_tets();
  if (x.rows() != nnode)
    fail("render: positions have ", x.rows(), " rows but the mesh has ", nnode, " nodes (pass one row per node)");
  if (!c.operational.empty() && int(c.operational.size()) != ntet)
    fail("render: the operational flags have ", c.operational.size(), " entries but the mesh has ", ntet,
         " tets (one per tet, or none)");
  if (!c.cut_faces.empty() && int(c.cut_faces.size()) != 4 * ntet)
    fail("render: the cut-face flags have ", c.cut_faces.size(), " entries but the mesh needs 4 x ", ntet,
         " (one per tet face, or none)");
  if (!c.tet_group.empty() && int(c.tet_group.size()) != ntet)
    fail("render: the tissue groups have ", c.tet_group.size(), " entries but the mesh has ", ntet,
         " tets (one per tet, or none)");
  for (size_t i = 0; i < c.tet_group.size(); ++i)
    if (c.tet_group[i] < 0) fail("render: tet ", i, " has tissue group ", c.tet_group[i], "; groups are >= 0");
  for (size_t i = 0; i < c.interface_nodes.size(); ++i)
    if (c.interface_nodes[i] < 0 || c.interface_nodes[i] >= nnode)
      fail("render: interface node ", i, " has id ", c.interface_nodes[i], ", outside the mesh's 0..", nnode - 1);
  if (!c.tool_labels.empty() && c.tool_labels.size() != c.tools.size())
    fail("render: ", c.tool_labels.size(), " tool labels for ", c.tools.size(), " tools (one per tool, or none)");
  for (size_t i = 0; i < c.manipulated.size(); ++i) {
    const ManipulatedNode& mn = c.manipulated[i];
    if (mn.node < 0 || mn.node >= nnode)
      fail("render: manipulated node ", i, " has id ", mn.node, ", outside the mesh's 0..", nnode - 1);
    if (!mn.line_end.allFinite()) fail("render: manipulated node ", mn.node, " has a non-finite line end");
  }
}

// Lines over a dark face colour are lightened, over a light one darkened.
Rgba wire_color(const Rgba& face) {
  const float lum = 0.30f * face[0] + 0.59f * face[1] + 0.11f * face[2];
  Rgba c = lum > 0.45f ? Rgba(0.35f * face) : Rgba(0.5f * face + Rgba(0.35f, 0.35f, 0.35f, 0.5f));
  c[3] = 1.0f;
  return c;
}

// Local face of tet t (kTetFaces numbering) holding nodes (a, b, c): the one
// opposite the tet's fourth node.
int local_face(const mesh::TetMesh& m, int t, int a, int b, int c) {
  for (int f = 0; f < 4; ++f) {
    const int v = m.tets(t, f);
    if (v != a && v != b && v != c) return f;
  }
  return 0;
}

enum FaceKind : unsigned char { kOperational, kNonoperational, kCut };

}  // namespace

// What a frame's scene needs from the topology alone (see SceneExtractor).
struct SceneExtractor::Topology {
  // The key: the topology and flags these were built from.
  int nnode = -1;
  Eigen::MatrixX4i tets;  // (ntet x 4)
  std::vector<char> operational, cut_faces;
  std::vector<int> tet_group;

  mesh::Surface surf;
  std::vector<unsigned char> kind;  // (nface) FaceKind
  int count[3] = {0, 0, 0};         // faces per FaceKind
  std::vector<int> start, adj;      // node -> surface faces (CSR: start (nnode + 1), adj (3 nface))
  std::vector<std::array<int, 3>> edges;  // unique surface edges (lo node, hi node, first face); on demand
  std::vector<std::array<int, 2>> rim;    // edges between cut and uncut faces; with `edges`
  bool have_edges = false;
  mesh::Surface inner;  // boundaries between tissue groups; on demand
  bool have_inner = false;
  std::vector<double> inner_depth;  // per node of `inner`: rest distance to the outer surface, m (with inner)
  int common_group = 0;             // the commonest tissue group (the parenchyma around inclusions)
  std::vector<char> on_cut;         // (nnode) node of a cut face
  int builds = 0;

  bool matches(const mesh::TetMesh& m, const SceneContent& c) const {
    return nnode == m.num_nodes() && tets.rows() == m.tets.rows() && tets == m.tets && operational == c.operational &&
           cut_faces == c.cut_faces && tet_group == c.tet_group;
  }

  void build(const mesh::TetMesh& m, const SceneContent& c) {
    nnode = m.num_nodes();
    tets = m.tets;
    operational = c.operational;
    cut_faces = c.cut_faces;
    tet_group = c.tet_group;
    surf = mesh::extract_surface(m);
    const int nface = int(surf.faces.rows());
    kind.assign(size_t(nface), kOperational);
    count[0] = count[1] = count[2] = 0;
    for (int f = 0; f < nface; ++f) {
      const int t = surf.face_tet(f);
      const bool op = c.operational.empty() || c.operational[size_t(t)];
      const bool cut = !c.cut_faces.empty() &&
                       c.cut_faces[size_t(4 * t + local_face(m, t, surf.faces(f, 0), surf.faces(f, 1), surf.faces(f, 2)))];
      kind[size_t(f)] = cut ? kCut : op ? kOperational : kNonoperational;
      ++count[kind[size_t(f)]];
    }
    start.assign(size_t(nnode) + 1, 0);
    adj.resize(size_t(3 * nface));
    for (int f = 0; f < nface; ++f)
      for (int k = 0; k < 3; ++k) ++start[size_t(surf.faces(f, k)) + 1];
    for (size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int f = 0; f < nface; ++f)
      for (int k = 0; k < 3; ++k) adj[size_t(fill[size_t(surf.faces(f, k))]++)] = f;
    on_cut.assign(size_t(nnode), 0);
    for (int f = 0; f < nface; ++f)
      if (kind[size_t(f)] == kCut)
        for (int k = 0; k < 3; ++k) on_cut[size_t(surf.faces(f, k))] = 1;
    edges.clear();
    rim.clear();
    have_edges = false;
    inner = {};
    have_inner = false;
    ++builds;
  }

  // Each surface edge once, with the first face that holds it (its colour),
  // and the incision's rim: the edges where a cut face meets one that is not
  // (lo node, hi node), so a closed incision still shows as an outline.
  void build_edges() {
    if (have_edges) return;
    const int nface = int(surf.faces.rows());
    std::vector<std::array<int, 3>> all;
    all.reserve(size_t(3 * nface));
    for (int f = 0; f < nface; ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = surf.faces(f, k), b = surf.faces(f, (k + 1) % 3);
        all.push_back({std::min(a, b), std::max(a, b), f});
      }
    std::sort(all.begin(), all.end());
    for (size_t i = 0, j = 0; i < all.size(); i = j) {
      bool cut = false, uncut = false;
      for (j = i; j < all.size() && all[j][0] == all[i][0] && all[j][1] == all[i][1]; ++j)
        (kind[size_t(all[j][2])] == kCut ? cut : uncut) = true;
      edges.push_back(all[i]);
      if (cut && uncut) rim.push_back({all[i][0], all[i][1]});
    }
    have_edges = true;
  }
  // The inner boundaries between tissue groups (mesh::group_boundaries), on demand.
  const mesh::Surface& inner_faces(const mesh::TetMesh& m) {
    if (have_inner) return inner;
    inner = mesh::group_boundaries(m, tet_group);
    // How deep each inclusion node lies below the outer surface (rest shape):
    // deeper parts show fainter, as through the capsule and the tissue above.
    inner_depth.assign(size_t(m.num_nodes()), 0.0);
    for (Eigen::Index f = 0; f < inner.faces.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int v = inner.faces(f, k);
        if (inner_depth[size_t(v)] > 0) continue;
        double best = std::numeric_limits<double>::infinity();
        for (int w : surf.nodes) best = std::min(best, (m.nodes.row(v) - m.nodes.row(w)).squaredNorm());
        inner_depth[size_t(v)] = std::sqrt(best) + 1e-300;
      }
    std::map<int, long> count;
    for (int g : tet_group) ++count[g];
    long most = -1;
    for (const auto& [g, n] : count)
      if (n > most) most = n, common_group = g;
    have_inner = true;
    return inner;
  }

  const std::vector<std::array<int, 3>>& surface_edges() {
    build_edges();
    return edges;
  }
  const std::vector<std::array<int, 2>>& rim_edges() {
    build_edges();
    return rim;
  }
};

SceneExtractor::SceneExtractor() = default;
SceneExtractor::~SceneExtractor() = default;
SceneExtractor::SceneExtractor(SceneExtractor&&) noexcept = default;
SceneExtractor& SceneExtractor::operator=(SceneExtractor&&) noexcept = default;

int SceneExtractor::topology_builds() const { return topo_ ? topo_->builds : 0; }

Scene extract_scene(const mesh::TetMesh& m, const Eigen::MatrixX3d& x, const SceneContent& content,
                    const RenderSettings& settings) {
  return SceneExtractor().extract(m, x, content, settings);
}

Scene SceneExtractor::extract(const mesh::TetMesh& m, const Eigen::MatrixX3d& x, const SceneContent& content,
                              const RenderSettings& settings) {
  check_settings(settings);
  check_content(m, x, content);
  if (!topo_ || !topo_->matches(m, content)) {
    // Built aside and swapped in whole: a throw leaves the old one intact.
    auto fresh = std::make_unique<Topology>();
    fresh->build(m, content);
    fresh->builds += topo_ ? topo_->builds : 0;
    topo_ = std::move(fresh);
  }
  const Topology& topo = *topo_;
  const mesh::Surface& surf = topo.surf;
  const Palette& pal = settings.palette;
  Scene scene;
  scene.width = settings.width;
  scene.height = settings.height;
  scene.msaa_samples = settings.msaa_samples;
  scene.background = pal.background;
  scene.tissue_faces_operational = topo.count[kOperational];
  scene.tissue_faces_nonoperational = topo.count[kNonoperational];
  scene.tissue_faces_cut = topo.count[kCut];

  for (int v : surf.nodes)
    if (!x.row(v).allFinite()) fail("render: the position of node ", v, " is not finite (did the solve diverge?)");
  const int nface = int(surf.faces.rows());
  const Rgba kind_color[3] = {pal.operational, pal.nonoperational, pal.cut};
  // A face's colour. paper: its region's, cut faces the cut colour.
  // clinical: its tet's tissue group's; a cut face that colour drawn
  // cut_tint of the way toward the cut colour, so the cut shows which tissue
  // it exposed (a lesion's cut face stays pale) and still reads as a wound.
  auto face_color = [&](int f) -> Rgba {
    const unsigned char k = topo.kind[size_t(f)];
    if (settings.style == Style::paper) return kind_color[k];
    const int g = content.tet_group.empty() ? 0 : content.tet_group[size_t(surf.face_tet(f))];
    const Rgba& tissue = pal.tissue[size_t(g) % pal.tissue.size()];
    if (k != kCut) return tissue;
    Rgba wound = pal.wound_shade * ((1.0f - pal.cut_tint) * tissue + pal.cut_tint * pal.cut);
    wound[3] = 1.0f;
    return wound;
  };
  const bool clinical = settings.style != Style::paper;
  // The wound colour a face's tissue shows when cut.
  auto face_color_of_cut = [&](int f) -> Rgba {
    const int g = content.tet_group.empty() ? 0 : content.tet_group[size_t(surf.face_tet(f))];
    const Rgba& tissue = pal.tissue[size_t(g) % pal.tissue.size()];
    return pal.wound_shade * ((1.0f - pal.cut_tint) * tissue + pal.cut_tint * pal.cut);
  };

  // A face's id in the label image: its tissue group's, or the cut's.
  auto face_label = [&](int f) -> std::uint32_t {
    if (topo.kind[size_t(f)] == kCut && content.cut_label) return content.cut_label;
    const int g = content.tet_group.empty() ? 0 : content.tet_group[size_t(surf.face_tet(f))];
    return size_t(g) < content.group_labels.size() ? content.group_labels[size_t(g)] : std::uint32_t(1 + g);
  };

  // Shading normals: per corner, the area-weighted mean of the normals of the
  // faces around that node that bend by less than the crease angle from this
  // face and lie on the same side of a cut (both cut faces or both not), so
  // smooth tissue looks smooth and box edges and an incision's lips stay
  // sharp however flat the cut meets the surface.
  std::vector<Eigen::Vector3d> area_normal(static_cast<size_t>(nface)), unit_normal(static_cast<size_t>(nface));
  for (int f = 0; f < nface; ++f) {
    const Eigen::Vector3d a = x.row(surf.faces(f, 0)), b = x.row(surf.faces(f, 1)), c = x.row(surf.faces(f, 2));
    area_normal[size_t(f)] = 0.5 * (b - a).cross(c - a);
    const double len = area_normal[size_t(f)].norm();
    unit_normal[size_t(f)] = len > 0 ? Eigen::Vector3d(area_normal[size_t(f)] / len) : Eigen::Vector3d::Zero();
  }
  const double cos_crease = std::cos(settings.crease_angle_deg * std::numbers::pi / 180.0);
  const bool flat = settings.crease_angle_deg == 0.0;
  scene.tissue.reserve(nface);
  for (int f = 0; f < nface; ++f) {
    Eigen::Vector3d p[3], n[3];
    const Eigen::Vector3d& nf = unit_normal[size_t(f)];
    for (int k = 0; k < 3; ++k) {
      const int v = surf.faces(f, k);
      p[k] = x.row(v);
      Eigen::Vector3d sum = area_normal[size_t(f)];
      if (!flat)
        for (int i = topo.start[size_t(v)]; i < topo.start[size_t(v) + 1]; ++i) {
          const int g = topo.adj[size_t(i)];
          if (g != f && (topo.kind[size_t(g)] == kCut) == (topo.kind[size_t(f)] == kCut) &&
              unit_normal[size_t(g)].dot(nf) >= cos_crease)
            sum += area_normal[size_t(g)];
        }
      const double len = sum.norm();
      n[k] = len > 0 ? Eigen::Vector3d(sum / len) : Eigen::Vector3d::UnitZ();  // degenerate face
    }
    const Rgba color = face_color(f);
    if (clinical && topo.kind[size_t(f)] == kCut) {
      scene.wound.label = face_label(f);
      scene.wound.add(p[0], p[1], p[2], n[0], n[1], n[2], color);
      continue;
    }
    scene.tissue.label = face_label(f);
    if (clinical && topo.count[kCut] > 0) {
      // The incision's margin: the outer surface darkens toward the wound
      // at the corners it shares with cut faces.
      Rgba c[3];
      for (int k = 0; k < 3; ++k) {
        c[k] = color;
        if (topo.on_cut[size_t(surf.faces(f, k))]) {
          c[k] = (1.0f - pal.margin_tint) * color + pal.margin_tint * face_color_of_cut(f);
          c[k][3] = 1.0f;
        }
      }
      scene.tissue.add(p[0], p[1], p[2], n[0], n[1], n[2], c[0], c[1], c[2]);
    } else {
      scene.tissue.add(p[0], p[1], p[2], n[0], n[1], n[2], color);
    }
  }

  // The incision's outline (depth-tested: the tissue is drawn pushed back,
  // so a line on its surface wins), present only once something was cut.
  scene.outline.size_px = clinical ? 1.5f * settings.line_width_px : settings.line_width_px;
  if (settings.incision_outline && topo.count[kCut] > 0)
    for (const auto& [a, b] : topo_->rim_edges()) {
      scene.outline.add(x.row(a).transpose(), pal.outline);
      scene.outline.add(x.row(b).transpose(), pal.outline);
    }

  // Inclusions (a lesion) seen through the tissue: their boundary faces in
  // their tissue colour, faint, with per-node normals smoothed over them.
  if (clinical && settings.show_inclusions && !content.tet_group.empty()) {
    const mesh::Surface& inner = topo_->inner_faces(m);
    const Eigen::MatrixX3d node_normal = mesh::vertex_normals(m, inner, x);
    const double size = (m.nodes.colwise().maxCoeff() - m.nodes.colwise().minCoeff()).norm();
    const double fade_length = std::max(1e-12, double(pal.inclusion_depth) * size);
    const Rgba& around = pal.tissue[size_t(topo_->common_group) % pal.tissue.size()];
    scene.inclusions.reserve(int(inner.faces.rows()));
    for (Eigen::Index f = 0; f < inner.faces.rows(); ++f) {
      // Seen through the tissue above it: 40 % of the way toward the
      // tissue's colour, fainter the deeper it lies.
      const Rgba own = pal.tissue[size_t(content.tet_group[size_t(inner.face_tet(f))]) % pal.tissue.size()];
      const Rgba base = 0.6f * own + 0.4f * around;
      Eigen::Vector3d p[3], n[3];
      Rgba c[3];
      for (int k = 0; k < 3; ++k) {
        const int v = inner.faces(f, k);
        if (!x.row(v).allFinite()) fail("render: the position of node ", v, " is not finite");
        p[k] = x.row(v);
        n[k] = node_normal.row(v).squaredNorm() > 0 ? Eigen::Vector3d(node_normal.row(v)) : Eigen::Vector3d::UnitZ();
        const double fade = std::exp(-topo_->inner_depth[size_t(v)] / fade_length * 1.2);
        c[k] = base;
        c[k][3] = float(pal.inclusion_alpha * (0.3 + 0.7 * fade));
      }
      scene.inclusions.add(p[0], p[1], p[2], n[0], n[1], n[2], c[0], c[1], c[2]);
    }
  }

  // Wireframe: each surface edge once, coloured after its first face.
  scene.wire.size_px = settings.wire_width_px;
  if (settings.wireframe)
    for (const auto& [a, b, f] : topo_->surface_edges()) {
      const Rgba c = wire_color(face_color(f));
      scene.wire.add(x.row(a).transpose(), c);
      scene.wire.add(x.row(b).transpose(), c);
    }

  scene.interface_points.size_px = settings.point_size_px;
  scene.interface_points.on_top = settings.interface_on_top;
  if (settings.show_interface)
    for (int v : content.interface_nodes) {
      if (!x.row(v).allFinite()) fail("render: the position of interface node ", v, " is not finite");
      scene.interface_points.add(x.row(v).transpose(), pal.interface_nodes);
    }

  // The manipulated nodes and their force lines show through the tissue;
  // the renderer draws the tools after them, so never over an instrument.
  scene.manipulated_points.size_px = 1.5f * settings.point_size_px;
  scene.manipulated_points.on_top = true;
  scene.force_lines.size_px = settings.line_width_px;
  scene.force_lines.on_top = true;
  for (const ManipulatedNode& mn : content.manipulated) {
    if (!settings.show_forces) break;
    if (!x.row(mn.node).allFinite()) fail("render: the position of manipulated node ", mn.node, " is not finite");
    scene.manipulated_points.add(x.row(mn.node).transpose(), pal.manipulated);
    scene.force_lines.add(x.row(mn.node).transpose(), pal.manipulated);
    scene.force_lines.add(mn.line_end, pal.manipulated);
  }

  // Load arrows: the shaft, and a head of two strokes a quarter of its length
  // long at 25 degrees, in a plane holding the shaft.
  scene.arrows.size_px = settings.line_width_px;
  scene.arrows.on_top = true;
  for (size_t i = 0; i < content.arrows.size() && settings.show_loads; ++i) {
    const Arrow& a = content.arrows[i];
    if (!a.from.allFinite() || !a.to.allFinite()) fail("render: arrow ", i, " has a non-finite end");
    const Eigen::Vector3d d = a.to - a.from;
    if (!(d.norm() > 0)) continue;
    const Eigen::Vector3d u = d.normalized(), side = u.unitOrthogonal();
    const double h = 0.25 * d.norm();
    scene.arrows.add(a.from, pal.arrow);
    scene.arrows.add(a.to, pal.arrow);
    for (double sgn : {-1.0, 1.0}) {
      scene.arrows.add(a.to, pal.arrow);
      scene.arrows.add(a.to - h * (std::cos(0.436) * u + sgn * std::sin(0.436) * side), pal.arrow);
    }
  }

  for (size_t i = 0; i < content.tools.size(); ++i) {
    scene.tools.label = i < content.tool_labels.size() ? content.tool_labels[i] : 0;
    try {
      add_tool(scene.tools, content.tools[i], settings.tool_segments, pal.tool, pal.tool_dark);
    } catch (const Error& e) {
      fail("render: tool ", i, ": ", e.what());
    }
  }

  // Framing uses the rest shape (stable while the tissue deforms); its
  // boundary surface holds every extreme point.
  std::vector<Eigen::Vector3d> frame;
  frame.reserve(surf.nodes.size());
  for (int v : surf.nodes) frame.push_back(m.node(v));
  scene.camera = resolve_camera(settings.camera, settings.width, settings.height, frame,
                                {&scene.tissue.positions, &scene.wound.positions, &scene.tools.positions,
                                 &scene.force_lines.positions, &scene.interface_points.positions});
  return scene;
}

}  // namespace softcut::render
