#include "sim/cutting.hpp"

#include <algorithm>
#include <array>
#include <numeric>
#include <map>

#include <Eigen/Geometry>

#include "core/error.hpp"
#include "core/timer.hpp"
#include "cut/blade.hpp"
#include "cut/detached.hpp"
#include "cut/rest_map.hpp"
#include "fem/anchoring.hpp"
#include "sim/model.hpp"

namespace softcut::sim {

namespace {

using FaceKey = std::array<int, 3>;

FaceKey sorted_face(int a, int b, int c) {
  FaceKey k = {a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

FaceKey local_face(const mesh::TetMesh& m, int t, int lf) {
  return sorted_face(m.tets(t, mesh::kTetFaces[lf][0]), m.tets(t, mesh::kTetFaces[lf][1]),
                     m.tets(t, mesh::kTetFaces[lf][2]));
}

// First cut: the Model's mesh and masks become the State's.
CutMesh initial_cut_mesh(const Model& m) {
  CutMesh cm;
  cm.mesh = m.mesh;
  cm.surface = m.surface;
  cm.tet_material = m.tet_material;
  cm.operational_tet = m.partition.operational_tet;
  cm.node_clamped.assign(size_t(m.mesh.num_nodes()), 0);
  for (int n : m.partition.fixed) cm.node_clamped[size_t(n)] = 1;
  cm.node_fixed = cm.node_clamped;
  cm.node_held.assign(size_t(m.mesh.num_nodes()), 0);
  cm.held_displacement = Eigen::MatrixX3d::Zero(m.mesh.num_nodes(), 3);
  cm.tet_detached.assign(size_t(m.mesh.num_tets()), 0);
  cm.cut_face.assign(size_t(4 * m.mesh.num_tets()), 0);
  cm.origin_tet.resize(size_t(m.mesh.num_tets()));
  std::iota(cm.origin_tet.begin(), cm.origin_tet.end(), 0);
  std::vector<char> locked(size_t(m.mesh.num_nodes()), 0);
  for (int n : m.partition.interface) locked[size_t(n)] = 1;  // make_cut_state adds nodes of nonoperational tets
  cm.cut = cut::make_cut_state(cm.mesh, cm.operational_tet, std::move(locked));
  return cm;
}

// Grows the per-tet / per-node masks after a cut step and refreshes the
// boundary; faces of the new boundary that are not rest-surface faces are
// flagged as cut faces.
void update_after_cut(const Model& m, CutMesh& cm, const cut::CutRecord& rec) {
  const int nt = cm.mesh.num_tets(), nn = cm.mesh.num_nodes();
  std::vector<fem::Material> mat(static_cast<size_t>(nt));
  std::vector<char> op(static_cast<size_t>(nt));
  for (int t = 0; t < nt; ++t) {
    const int parent = rec.tet_parent[size_t(t)];
    mat[size_t(t)] = cm.tet_material[size_t(parent)];
    op[size_t(t)] = cm.operational_tet[size_t(parent)];
  }
  std::vector<int> origin(static_cast<size_t>(nt));
  for (int t = 0; t < nt; ++t) origin[size_t(t)] = cm.origin_tet[size_t(rec.tet_parent[size_t(t)])];
  cm.tet_material = std::move(mat);
  cm.operational_tet = std::move(op);
  cm.origin_tet = std::move(origin);
  cm.node_clamped.resize(size_t(nn), 0);
  for (const cut::NewNode& v : rec.new_nodes) {
    bool fixed = true;  // fixed when every contributing parent is (a clamp stays a clamp)
    for (int k = 0; k < 2; ++k)
      if (v.parent[size_t(k)] >= 0 && v.weight[size_t(k)] != 0)
        fixed &= cm.node_clamped[size_t(v.parent[size_t(k)])] != 0;
    cm.node_clamped[size_t(v.id)] = fixed;
  }
  // Cut faces: boundary faces that do not lie on a rest boundary face of the
  // rest tet they come from (children of split outer faces stay outer faces).
  cm.surface = mesh::extract_surface(cm.mesh);
  std::map<int, std::vector<int>> rest_faces;  // rest tet -> its local faces on the rest boundary
  for (Eigen::Index f = 0; f < m.surface.faces.rows(); ++f) {
    const int t = m.surface.face_tet(f);
    const FaceKey key = sorted_face(m.surface.faces(f, 0), m.surface.faces(f, 1), m.surface.faces(f, 2));
    for (int lf = 0; lf < 4; ++lf)
      if (local_face(m.mesh, t, lf) == key) rest_faces[t].push_back(lf);
  }
  cm.cut_face.assign(size_t(4 * nt), 0);
  for (Eigen::Index f = 0; f < cm.surface.faces.rows(); ++f) {
    const int t = cm.surface.face_tet(f);
    const FaceKey key = sorted_face(cm.surface.faces(f, 0), cm.surface.faces(f, 1), cm.surface.faces(f, 2));
    bool outer = false;
    const auto it = rest_faces.find(cm.origin_tet[size_t(t)]);
    if (it != rest_faces.end())
      for (int lf : it->second) {
        const int T = it->first;
        const Eigen::Vector3d p = m.mesh.node(m.mesh.tets(T, mesh::kTetFaces[lf][0]));
        const Eigen::Vector3d q = m.mesh.node(m.mesh.tets(T, mesh::kTetFaces[lf][1]));
        const Eigen::Vector3d r = m.mesh.node(m.mesh.tets(T, mesh::kTetFaces[lf][2]));
        const Eigen::Vector3d n = (q - p).cross(r - p);
        const double tol = 1e-9 * n.norm() * std::max({(q - p).norm(), (r - p).norm(), 1e-300});
        bool on = true;
        for (int v : key) on &= std::abs(n.dot(cm.mesh.node(v) - p)) <= tol;
        outer |= on;
      }
    if (outer) continue;
    for (int lf = 0; lf < 4; ++lf)
      if (local_face(cm.mesh, t, lf) == key) cm.cut_face[size_t(4 * t + lf)] = 1;
  }
}

// After a step (u: displacements already mapped onto the new nodes): finds
// the parts that nothing anchors, holds their unclamped nodes (at their held
// value if they were held before, else at u: where they were when they
// separated) and refreshes node_fixed. Returns the pieces this step cut free
// (a piece is new when one of its tets comes from a tet that was attached).
std::vector<cut::DetachedPiece> update_detached(CutMesh& cm, const cut::CutRecord& rec, const Eigen::MatrixX3d& u) {
  const int nn = cm.mesh.num_nodes(), nt = cm.mesh.num_tets();
  const std::vector<char> was_detached = std::move(cm.tet_detached);  // (pre-step ntet)
  const std::vector<char> was_held = std::move(cm.node_held);         // (pre-step nnode)
  const Eigen::MatrixX3d old_held = std::move(cm.held_displacement);
  cm.tet_detached.assign(size_t(nt), 0);
  cm.node_held.assign(size_t(nn), 0);
  cm.held_displacement = Eigen::MatrixX3d::Zero(nn, 3);
  std::vector<cut::DetachedPiece> fresh;
  for (cut::DetachedPiece& piece : cut::find_detached(cm.mesh, cm.node_clamped)) {
    bool is_new = false;
    for (int t : piece.tets) {
      cm.tet_detached[size_t(t)] = 1;
      is_new |= !was_detached[size_t(rec.tet_parent[size_t(t)])];
    }
    for (int v : piece.nodes) {
      if (cm.node_clamped[size_t(v)]) continue;
      cm.node_held[size_t(v)] = 1;
      const bool before = size_t(v) < was_held.size() && was_held[size_t(v)];
      cm.held_displacement.row(v) = before ? old_held.row(v) : u.row(v);
    }
    if (is_new) fresh.push_back(std::move(piece));
  }
  cm.node_fixed.resize(size_t(nn));
  for (int v = 0; v < nn; ++v) cm.node_fixed[size_t(v)] = cm.node_clamped[size_t(v)] || cm.node_held[size_t(v)];
  return fresh;
}

bool blade_in_box(const mesh::TetMesh& mesh, const Eigen::MatrixX3d& u, const tools::ToolState& ts, double radius) {
  const Eigen::MatrixX3d x = mesh.nodes + u;
  const Eigen::Vector3d lo = x.colwise().minCoeff().transpose().array() - radius;
  const Eigen::Vector3d hi = x.colwise().maxCoeff().transpose().array() + radius;
  for (double a : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    const Eigen::Vector3d p = ts.blade_a + a * (ts.blade_b - ts.blade_a);
    if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) return true;
  }
  return false;
}

bool changed_mesh(const cut::CutRecord& r) {
  return !r.new_nodes.empty() || !r.changed_tets.empty() || r.nodes_snapped > 0 || r.faces_separated > 0;
}

}  // namespace

const mesh::TetMesh& current_mesh(const Model& m, const State& s) { return s.cut ? s.cut->mesh : m.mesh; }
const mesh::Surface& current_surface(const Model& m, const State& s) { return s.cut ? s.cut->surface : m.surface; }

bool is_fixed_node(const Model& m, const State& s, int n) {
  if (s.cut) return s.cut->node_fixed[size_t(n)] != 0;
  return m.partition.node_set[size_t(n)] == hybrid::NodeSet::fixed;
}

bool is_held_node(const State& s, int n) {
  return s.cut && n >= 0 && size_t(n) < s.cut->node_held.size() && s.cut->node_held[size_t(n)];
}

hybrid::NodeSet node_set(const Model& m, const State& s, int n) {
  if (n < m.mesh.num_nodes()) return m.partition.node_set[size_t(n)];
  return is_fixed_node(m, s, n) ? hybrid::NodeSet::fixed : hybrid::NodeSet::operational;
}

std::vector<CutEvent> cut_stage(const Model& m, State& s, int frame, double t) {
  std::vector<CutEvent> events;
  for (size_t k = 0; k < s.tools.size() && k < s.tool_specs.size(); ++k) {
    const tools::ToolSpec& spec = s.tool_specs[k];
    tools::ToolState& ts = s.tools[k];
    if (spec.kind != tools::ToolSpec::Kind::scalpel) continue;
    const bool active = spec.enabled && t >= spec.active_from && t <= spec.active_until;
    const bool pressing = ts.engaged && ts.pressure >= spec.cut_pressure;
    if (!active || !ts.has_prev || !(pressing || ts.in_cut)) {
      ts.in_cut = false;
      ts.has_rest = false;
      continue;
    }
    if (!ts.prev_a.allFinite() || !ts.blade_a.allFinite() || !ts.prev_b.allFinite() || !ts.blade_b.allFinite())
      fail(spec.where.empty() ? "" : spec.where + ": ", "scalpel '", spec.name, "': blade position is not finite at t = ",
           t, " s");
    Timer timer;
    if (!s.cut) s.cut = std::make_unique<CutMesh>(initial_cut_mesh(m));
    CutMesh& cm = *s.cut;
    const bool continuing = ts.in_cut && ts.has_rest;
    if (!ts.in_cut) cut::begin_stroke(cm.cut);  // the blade enters the tissue: a new cut surface
    // Blade corners in the rest configuration, through the operational tets
    // only: their nodes (sets 1 and I) are solved every frame, interior
    // nonoperational rows may be stale. The previous pose is NOT mapped again:
    // within a stroke it keeps the rest image the previous step swept to.
    // Mapping it with this frame's displacement would move the edge the two
    // steps share whenever the field changed in between (a moving load, or the
    // tissue relaxing after the previous cut), and an edge crossing that lies
    // in the gap between the two rest quads would be tested by neither step.
    auto to_rest = [&](const Eigen::Vector3d& x) {
      return cut::deformed_to_rest(cm.mesh, s.displacement, x, cm.operational_tet);
    };
    const bool triangular = spec.blade_back.squaredNorm() > 0;
    const Eigen::Vector3d ra0 = continuing ? ts.rest_a : to_rest(ts.prev_a);
    const Eigen::Vector3d rb0 = continuing ? ts.rest_b : to_rest(ts.prev_b);
    const Eigen::Vector3d ra1 = to_rest(ts.blade_a), rb1 = to_rest(ts.blade_b);
    cut::SweptSurface rest = cut::sweep_segment(ra0, rb0, ra1, rb1);
    Eigen::Vector3d rc1 = Eigen::Vector3d::Zero();
    if (triangular) {  // triangular blade: its area now and the sweep of its other edges
      const Eigen::Vector3d rc0 = continuing ? ts.rest_c : to_rest(ts.prev_c);
      rc1 = to_rest(ts.blade_c);
      cut::append(rest, cut::sweep_triangle(ra1, rb1, rc1));
      cut::append(rest, cut::sweep_segment(rb0, rc0, rb1, rc1));
      cut::append(rest, cut::sweep_segment(rc0, ra0, rc1, ra1));
    }
    cut::CutOptions opt;
    opt.snap_fraction = m.spec.cutting.snap_fraction;
    opt.min_dihedral_deg = m.spec.cutting.min_dihedral_deg;
    const cut::CutRecord rec = cut::cut_step(cm.mesh, cm.cut, rest, opt);
    const bool changed = changed_mesh(rec);
    // The tissue yields under the blade: no pressing force while cutting.
    // The stroke goes on while the blade cuts, presses, or stays within the
    // deformed body's box (a step may cross no edge while inside).
    ts.cutting = true;
    ts.in_cut = changed || pressing || blade_in_box(cm.mesh, s.displacement, ts, spec.radius);
    // Rest coordinates stay valid across the step (no node moves; new nodes lie
    // on rest edges), so the next step of this stroke starts from these.
    ts.rest_a = ra1, ts.rest_b = rb1, ts.rest_c = rc1;
    ts.has_rest = ts.in_cut;
    for (auto& f : ts.forces) f.setZero();
    ts.total_force.setZero();
    const double cut_ms = timer.ms();

    CutEvent ev;
    ev.frame = frame, ev.time = t, ev.tool = spec.name;
    ev.tets_split = int(rec.split_tets.size());
    ev.nodes_added = int(rec.new_nodes.size());
    ev.edges_split = rec.edges_split, ev.nodes_snapped = rec.nodes_snapped;
    ev.faces_separated = rec.faces_separated, ev.faces_pending = rec.faces_pending;
    ev.worst_new_dihedral_deg = rec.worst_new_dihedral_deg, ev.worst_dihedral_deg = rec.worst_dihedral_deg;
    ev.cg_iterations_before = s.last_cg_iterations;
    for (const auto& w : rec.warnings) {
      ev.warnings.push_back(w);
      s.warnings.push_back(cat("frame ", frame, " (t = ", t, " s), scalpel '", spec.name, "': ", w));
    }
    timer.reset();
    if (changed) {
      update_after_cut(m, cm, rec);
      s.displacement = cut::map_node_field(rec, s.displacement);
      const Eigen::Index old = s.forces.rows();
      s.forces.conservativeResize(cm.mesh.num_nodes(), 3);
      s.forces.bottomRows(s.forces.rows() - old).setZero();
      // Pieces cut free are held where they are (DESIGN.md invariants: the
      // rest stays exact; a floating piece would make the system singular).
      for (const cut::DetachedPiece& piece : update_detached(cm, rec, s.displacement)) {
        ++cm.detached_pieces;
        ++ev.pieces_freed;
        ev.tets_freed += int(piece.tets.size());
        ev.nodes_freed += int(piece.nodes.size());
        const std::string pinned =
            piece.fixed_nodes > 0 ? cat(" (its ", piece.fixed_nodes, " fixed nodes lie at one point or on one line)")
                                  : std::string();
        const std::string w =
            cat("piece of ", piece.tets.size(), " tets / ", piece.nodes.size(), " nodes (smallest node id ",
                piece.nodes.front(), ") cut free at frame ", frame, pinned,
                "; held at its displacement at separation (no rigid-body motion is simulated); loads and tool "
                "forces on it are ignored");
        ev.warnings.push_back(w);
        s.warnings.push_back(cat("frame ", frame, " (t = ", t, " s), scalpel '", spec.name, "': ", w));
      }
      m.solver->apply_cut(cm, rec, s.solver_run);
      ts.cut_events++;
    }
    ev.nodes_after = cm.mesh.num_nodes(), ev.tets_after = cm.mesh.num_tets();
    ev.cut_ms = cut_ms, ev.rebuild_ms = timer.ms();
    if (changed) events.push_back(ev);
  }
  for (const auto& e : events) s.cut_events.push_back(e);
  return events;
}

void drop_loads_on_held(State& s, int frame, double t) {
  if (!s.cut || s.cut->detached_pieces == 0) return;
  CutMesh& cm = *s.cut;
  auto warn_once = [&](const std::string& key, const std::string& what) {
    if (std::find(cm.ignored_on_held.begin(), cm.ignored_on_held.end(), key) != cm.ignored_on_held.end()) return;
    cm.ignored_on_held.push_back(key);
    s.warnings.push_back(cat("frame ", frame, " (t = ", t, " s), ", what,
                             " acts on a piece cut free; its force there is ignored (the piece is held)"));
  };
  // Tool forces on fixed (and so held) nodes never reach s.forces (step());
  // rows of held nodes that carry a force come from loads.
  for (const ActiveLoad& l : s.loads)
    for (int n : l.nodes)
      if (is_held_node(s, n) && s.forces.row(n).squaredNorm() > 0) {
        warn_once("load:" + l.spec.name, cat("load '", l.spec.name, "'"));
        break;
      }
  for (size_t i = 0; i < s.tools.size() && i < s.tool_specs.size(); ++i) {
    const tools::ToolState& ts = s.tools[i];
    const bool spring = tools::is_implicit_spring(s.tool_specs[i]);
    for (size_t k = 0; k < ts.nodes.size(); ++k)
      if (is_held_node(s, ts.nodes[k]) && (spring || (k < ts.forces.size() && ts.forces[k].squaredNorm() > 0))) {
        warn_once("tool:" + s.tool_specs[i].name, cat("tool '", s.tool_specs[i].name, "'"));
        break;
      }
  }
  for (int v = 0; v < int(cm.node_held.size()) && v < s.forces.rows(); ++v)
    if (cm.node_held[size_t(v)]) s.forces.row(v).setZero();
}

void hold_detached(State& s) {
  if (!s.cut || s.cut->detached_pieces == 0) return;
  const CutMesh& cm = *s.cut;
  for (int v = 0; v < int(cm.node_held.size()) && v < s.displacement.rows(); ++v)
    if (cm.node_held[size_t(v)]) s.displacement.row(v) = cm.held_displacement.row(v);
}

CuttingSummary cutting_summary(const Model& m, const State& s) {
  CuttingSummary c;
  const mesh::TetMesh& mesh = current_mesh(m, s);
  c.events = int(s.cut_events.size());
  for (const CutEvent& e : s.cut_events) c.nodes_added += e.nodes_added, c.faces_separated += e.faces_separated;
  c.nodes = mesh.num_nodes();
  c.tets = mesh.num_tets();
  c.faces_pending = s.cut ? int(s.cut->cut.pending.size()) : 0;
  c.components = count_components(mesh);
  std::vector<char> fixed(size_t(mesh.num_nodes()), 0);
  c.pieces = int(fem::anchor_parts(mesh, {}, fixed).parts.size());
  c.detached = s.cut ? s.cut->detached_pieces : 0;
  return c;
}

DetachedCounts detached_counts(const State& s) {
  DetachedCounts c;
  if (!s.cut) return c;
  const CutMesh& cm = *s.cut;
  c.pieces = cm.detached_pieces;
  std::vector<char> node(size_t(cm.mesh.num_nodes()), 0);
  for (int t = 0; t < cm.mesh.num_tets(); ++t) {
    if (!cm.tet_detached[size_t(t)]) continue;
    ++c.tets;
    for (int k = 0; k < 4; ++k) node[size_t(cm.mesh.tets(t, k))] = 1;
  }
  for (char v : node) c.nodes += v;
  return c;
}

int count_components(const mesh::TetMesh& mesh) {
  std::vector<int> parent(size_t(mesh.num_nodes()));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[size_t(v)] != v) v = parent[size_t(v)] = parent[size_t(parent[size_t(v)])];
    return v;
  };
  std::vector<char> used(size_t(mesh.num_nodes()), 0);
  for (int t = 0; t < mesh.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) {
      used[size_t(mesh.tets(t, k))] = 1;
      if (k > 0) {
        const int a = find(mesh.tets(t, 0)), b = find(mesh.tets(t, k));
        if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
      }
    }
  int n = 0;
  for (int v = 0; v < mesh.num_nodes(); ++v) n += used[size_t(v)] && find(v) == v;
  return n;
}

}  // namespace softcut::sim
