#include "sim/cutting.hpp"

#include <algorithm>
#include <array>
#include <limits>
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

using Pose = std::array<Eigen::Vector3d, 3>;  // blade corners a, b, c (c: a triangular blade's third), m

// The blade's pose with its centre on the path at time t.
Pose pose_at(const tools::ToolSpec& spec, double t) {
  Pose p;
  const Eigen::Vector3d centre = tools::evaluate(spec.path, t);
  tools::blade_edge(spec, centre, p[0], p[1]);
  p[2] = centre + spec.blade_back;
  return p;
}

// How deep the blade edge a-b lies in the tissue: the largest distance to the
// deformed surface of a sample point of the edge inside the deformed body
// (0 when none is), m; `at` gets that point.
double blade_depth(const Model& m, const State& s, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                   Eigen::Vector3d& at) {
  const mesh::TetMesh& mesh = current_mesh(m, s);
  const mesh::Surface& surface = current_surface(m, s);
  const Eigen::MatrixX3d x = mesh.nodes + s.displacement;
  const Eigen::Vector3d lo = x.colwise().minCoeff().transpose(), hi = x.colwise().maxCoeff().transpose();
  double deepest = 0;
  for (double f : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    const Eigen::Vector3d p = a + f * (b - a);
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    if (cut::deformed_tet_at(mesh, s.displacement, p) < 0) continue;
    double depth = std::numeric_limits<double>::infinity();
    for (Eigen::Index k = 0; k < surface.faces.rows(); ++k) {
      Eigen::Matrix3d tri;
      for (int j = 0; j < 3; ++j) tri.col(j) = x.row(surface.faces(k, j)).transpose();
      depth = std::min(depth, cut::point_triangle_distance(p, tri));
    }
    if (depth > deepest) deepest = depth, at = p;
  }
  return deepest;
}

// A new stroke cuts from where the blade entered the tissue. When its pose at
// `t_prev` already lies inside (deeper than its radius, in this frame's
// configuration: it sank in pressing below cut_pressure, or the tissue it had
// pushed away sprang back around it), the poses along its path back to the
// last one outside are put in front of `poses` (which holds the pose at
// t_prev): whole frames back first, then the crossing bisected.
void prepend_entry(const Model& m, const State& s, const tools::ToolSpec& spec, double t_prev,
                   std::vector<Pose>& poses) {
  Eigen::Vector3d at;
  auto inside = [&](double t) {
    const Pose p = pose_at(spec, t);
    return blade_depth(m, s, p[0], p[1], at) > spec.radius;
  };
  if (!inside(t_prev)) return;
  const double t_first = std::max(0.0, spec.active_from);
  double t_in = t_prev, t_out = -1;
  for (int k = 1; k <= 64 && t_in > t_first; ++k) {
    const double tk = std::max(t_first, t_prev - k * m.dt);
    if (!inside(tk)) {
      t_out = tk;
      break;
    }
    t_in = tk;
    poses.insert(poses.begin(), pose_at(spec, tk));
  }
  if (t_out < 0) return;  // no pose outside within reach: cut from the deepest found
  for (int i = 0; i < 12; ++i) {
    const double mid = 0.5 * (t_out + t_in);
    (inside(mid) ? t_in : t_out) = mid;
  }
  poses.insert(poses.begin(), pose_at(spec, t_out));
}

// A scalpel inside the tissue that is not cutting either starts there (a
// cut cannot begin inside) or got there without pressing at its cut_pressure
// and lost contact: it would never cut through, and say nothing. Refuse.
[[noreturn]] void refuse_blade_inside(const tools::ToolSpec& spec, const tools::ToolState& ts, double t, double depth,
                                      const Eigen::Vector3d& p, bool starts_inside) {
  const std::string how =
      starts_inside ? std::string("its path starts inside the tissue")
      : ts.touch_time < 0
          ? std::string("it never touched the surface")
          : cat("it last touched the surface at t = ", ts.touch_time, " s pressing at ", ts.touch_pressure,
                " Pa, below its cut_pressure = ", spec.cut_pressure, " Pa, and lost contact");
  fail(spec.where.empty() ? "" : spec.where + ": ", "scalpel '", spec.name, "': at t = ", t, " s its edge is ",
       depth * 1e3, " mm inside the tissue (at ", p.x(), ", ", p.y(), ", ", p.z(), " m) but it is not cutting: ", how,
       ". A blade cuts from the frame in which it presses at cut_pressure: start its path above the surface and let it "
       "press at cut_pressure (a contact force of ",
       spec.cut_pressure * spec.blade_length * 2 * spec.radius, " N for this blade) before it sinks in, or lower "
       "cut_pressure");
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
    if (!active || !(pressing || ts.in_cut)) {
      ts.in_cut = false;
      ts.has_rest = false;
      if (!active) {
        ts.outside_seen = false;
        continue;
      }
      // Not cutting. A blade inside the tissue without contact, or whose path
      // starts inside, would never cut: refuse it.
      Eigen::Vector3d at;
      const double depth = blade_depth(m, s, ts.blade_a, ts.blade_b, at);
      if (depth > spec.radius && (!ts.outside_seen || !ts.engaged))
        refuse_blade_inside(spec, ts, t, depth, at, !ts.outside_seen);
      ts.outside_seen = ts.outside_seen || depth <= spec.radius;
      continue;
    }
    if (!ts.blade_a.allFinite() || !ts.blade_b.allFinite() ||
        (ts.has_prev && (!ts.prev_a.allFinite() || !ts.prev_b.allFinite())))
      fail(spec.where.empty() ? "" : spec.where + ": ", "scalpel '", spec.name, "': blade position is not finite at t = ",
           t, " s");
    Timer timer;
    if (!s.cut) s.cut = std::make_unique<CutMesh>(initial_cut_mesh(m));
    CutMesh& cm = *s.cut;
    const bool continuing = ts.in_cut && ts.has_rest;
    if (!ts.in_cut) {  // the blade enters the tissue: a new cut surface
      cut::begin_stroke(cm.cut);
      ts.warned_uncuttable = false;
    }
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
    auto pose_to_rest = [&](const Pose& p) {
      return Pose{to_rest(p[0]), to_rest(p[1]), triangular ? to_rest(p[2]) : Eigen::Vector3d::Zero()};
    };
    // Rest poses swept this step, oldest first; a new stroke starts where the
    // edge entered the tissue (prepend_entry; not for a tip the script moves).
    std::vector<Pose> poses;
    if (continuing) {
      poses.push_back({ts.rest_a, ts.rest_b, ts.rest_c});
    } else if (ts.has_prev) {  // (on its first frame a blade pressing already starts a stroke there)
      std::vector<Pose> from{{ts.prev_a, ts.prev_b, ts.prev_c}};
      if (!ts.override_tip) prepend_entry(m, s, spec, m.frame_time(frame - 1), from);
      for (const Pose& p : from) poses.push_back(pose_to_rest(p));
    } else {
      Eigen::Vector3d at;
      const double depth = blade_depth(m, s, ts.blade_a, ts.blade_b, at);
      if (depth > spec.radius) refuse_blade_inside(spec, ts, t, depth, at, true);
    }
    poses.push_back(pose_to_rest({ts.blade_a, ts.blade_b, ts.blade_c}));
    const Pose& now = poses.back();
    cut::SweptSurface rest;
    for (size_t i = 1; i < poses.size(); ++i) {
      const Pose &p0 = poses[i - 1], &p1 = poses[i];
      cut::append(rest, cut::sweep_segment(p0[0], p0[1], p1[0], p1[1]));
      if (!triangular) continue;  // triangular blade: its area now and the sweep of its other edges
      if (i + 1 == poses.size()) cut::append(rest, cut::sweep_triangle(p1[0], p1[1], p1[2]));
      cut::append(rest, cut::sweep_segment(p0[1], p0[2], p1[1], p1[2]));
      cut::append(rest, cut::sweep_segment(p0[2], p0[0], p1[2], p1[0]));
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
    ts.rest_a = now[0], ts.rest_b = now[1], ts.rest_c = now[2];
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
    std::vector<std::string> warnings = rec.warnings;
    // A blade over tissue it may not cut (outside s:operational{}) that cut
    // nothing would otherwise pass silently: once per stroke.
    if (warnings.empty() && rec.uncuttable_tets_crossed > 0 && rec.new_nodes.empty() && rec.faces_separated == 0 &&
        !ts.warned_uncuttable) {
      ts.warned_uncuttable = true;
      warnings.push_back(cat("the blade (centre ", ts.tip.x(), ", ", ts.tip.y(), ", ", ts.tip.z(), " m) reaches ",
                             rec.uncuttable_tets_crossed,
                             " tet(s) outside the operational region, which cannot be cut, and cut nothing; only "
                             "s:operational{} tissue is cut: move the path or grow the operational region"));
    }
    for (const auto& w : warnings) {
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
      // Grips the cut went through: each point onto a face of one side.
      const Eigen::MatrixX3d x = cm.mesh.nodes + s.displacement;
      for (tools::ToolState& other : s.tools) tools::rebind_grip(other, x, cm.surface);
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
