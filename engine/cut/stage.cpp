#include "cut/stage.hpp"

#include <algorithm>
#include <array>
#include <limits>

#include "core/error.hpp"
#include "core/timer.hpp"
#include "core/warning.hpp"
#include "cut/blade.hpp"
#include "cut/rest_map.hpp"
#include "fem/anchoring.hpp"
#include "tools/path.hpp"

namespace softcut::cut {

namespace {

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
double blade_depth(const RestBody& rest, const StageFrame& s, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                   Eigen::Vector3d& at) {
  const mesh::TetMesh& mesh = s.cut ? s.cut->mesh : rest.mesh;
  const mesh::Surface& surface = s.cut ? s.cut->surface : rest.surface;
  const Eigen::MatrixX3d x = mesh.nodes + s.displacement;
  const Eigen::Vector3d lo = x.colwise().minCoeff().transpose(), hi = x.colwise().maxCoeff().transpose();
  double deepest = 0;
  for (double f : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    const Eigen::Vector3d p = a + f * (b - a);
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    if (deformed_tet_at(mesh, s.displacement, p) < 0) continue;
    double depth = std::numeric_limits<double>::infinity();
    for (Eigen::Index k = 0; k < surface.faces.rows(); ++k) {
      Eigen::Matrix3d tri;
      for (int j = 0; j < 3; ++j) tri.col(j) = x.row(surface.faces(k, j)).transpose();
      depth = std::min(depth, point_triangle_distance(p, tri));
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
void prepend_entry(const RestBody& rest, const StageFrame& s, const tools::ToolSpec& spec, double t_prev,
                   std::vector<Pose>& poses) {
  Eigen::Vector3d at;
  auto inside = [&](double t) {
    const Pose p = pose_at(spec, t);
    return blade_depth(rest, s, p[0], p[1], at) > spec.radius;
  };
  if (!inside(t_prev)) return;
  const double t_first = std::max(0.0, spec.start);
  double t_in = t_prev, t_out = -1;
  for (int k = 1; k <= 64 && t_in > t_first; ++k) {
    const double tk = std::max(t_first, t_prev - k * s.dt);
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

bool changed_mesh(const CutRecord& r) {
  return !r.new_nodes.empty() || !r.changed_tets.empty() || r.nodes_snapped > 0 || r.faces_separated > 0;
}

// " by the cuts of strokes begun at ..." for a piece cut free: the strokes
// its nodes last joined the cut in, and, when several, what can make
// strokes that never met free a piece (issue #40 item 9: eight parallel
// strokes 0.6 mm apart, inside the 1.5 mm snap distance, freed 91 tets).
std::string by_strokes(const CutMesh& cm, const DetachedPiece& piece) {
  std::vector<int> strokes;
  for (int v : piece.nodes)
    if (size_t(v) < cm.cut.cut_stroke.size() && cm.cut.cut_stroke[size_t(v)] > 0)
      strokes.push_back(cm.cut.cut_stroke[size_t(v)]);
  std::sort(strokes.begin(), strokes.end());
  strokes.erase(std::unique(strokes.begin(), strokes.end()), strokes.end());
  if (strokes.empty()) return {};
  std::string out = strokes.size() == 1 ? " by the cut of the stroke begun at " : " by the cuts of the strokes begun at ";
  for (size_t i = 0; i < strokes.size(); ++i) {
    const size_t k = size_t(strokes[i]);
    out += i == 0 ? "" : i + 1 == strokes.size() ? " and " : ", ";
    if (k < cm.stroke_begun.size()) out += cat("t = ", cm.stroke_begun[k].second, " s ('", cm.stroke_begun[k].first, "')");
    else out += cat("stroke ", k);
  }
  if (strokes.size() > 1)
    out += " (strokes closer together than the snap distance merge into one cut on this mesh, and tissue between "
           "them can come free where no blade closed it: if these strokes did not meet, refine the mesh or space "
           "them farther apart)";
  return out;
}

}  // namespace

std::vector<CutEvent> cut_stage(const RestBody& rest, StageFrame& s) {
  const int frame = s.frame;
  const double t = s.t;
  std::vector<CutEvent> events;
  for (size_t k = 0; k < s.tools.size() && k < s.specs.size(); ++k) {
    const tools::ToolSpec& spec = s.specs[k];
    tools::ToolState& ts = s.tools[k];
    if (spec.kind != tools::ToolSpec::Kind::scalpel) continue;
    const bool active = spec.enabled && t >= spec.start && t <= spec.stop;
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
      const double depth = blade_depth(rest, s, ts.blade_a, ts.blade_b, at);
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
    if (!s.cut) s.cut = std::make_unique<CutMesh>(initial_cut_mesh(rest));
    CutMesh& cm = *s.cut;
    const bool continuing = ts.in_cut && ts.has_rest;
    if (!ts.in_cut) {  // the blade enters the tissue: a new cut surface
      begin_stroke(cm.cut);
      cm.stroke_begun.resize(size_t(cm.cut.stroke) + 1);
      cm.stroke_begun[size_t(cm.cut.stroke)] = {spec.name, t};
      ts.warned_uncuttable = ts.warned_locked_snap = false;
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
      return deformed_to_rest(cm.mesh, s.displacement, x, cm.operational_tet);
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
      if (!ts.override_tip) prepend_entry(rest, s, spec, s.t_prev, from);
      for (const Pose& p : from) poses.push_back(pose_to_rest(p));
    } else {
      Eigen::Vector3d at;
      const double depth = blade_depth(rest, s, ts.blade_a, ts.blade_b, at);
      if (depth > spec.radius) refuse_blade_inside(spec, ts, t, depth, at, true);
    }
    poses.push_back(pose_to_rest({ts.blade_a, ts.blade_b, ts.blade_c}));
    const Pose& now = poses.back();
    SweptSurface swept;
    for (size_t i = 1; i < poses.size(); ++i) {
      const Pose &p0 = poses[i - 1], &p1 = poses[i];
      append(swept, sweep_segment(p0[0], p0[1], p1[0], p1[1]));
      if (!triangular) continue;  // triangular blade: its area now and the sweep of its other edges
      if (i + 1 == poses.size()) append(swept, sweep_triangle(p1[0], p1[1], p1[2]));
      append(swept, sweep_segment(p0[1], p0[2], p1[1], p1[2]));
      append(swept, sweep_segment(p0[2], p0[0], p1[2], p1[0]));
    }
    const CutRecord rec = cut_step(cm.mesh, cm.cut, swept, s.options);
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
    ev.cg_iterations_before = s.cg_iterations_before;
    std::vector<std::string> warnings = rec.warnings;
    // A blade over tissue it may not cut (outside s:operational{}) that cut
    // nothing would otherwise pass silently: once per stroke.
    if (warnings.empty() && rec.uncuttable_tets_crossed > 0 && rec.new_nodes.empty() && rec.faces_separated == 0 &&
        !ts.warned_uncuttable) {
      ts.warned_uncuttable = true;
      warnings.push_back(coded_warning(
          "blade_outside_operational",
          cat("the blade (centre ", ts.tip.x(), ", ", ts.tip.y(), ", ", ts.tip.z(), " m) reaches ",
              rec.uncuttable_tets_crossed,
              " tet(s) outside the operational region, which cannot be cut, and cut nothing; only s:operational{} "
              "tissue is cut: move the path or grow the operational region")));
    }
    // A blade inside the operational region but within the snap distance of
    // its boundary snaps onto locked nodes and opens nothing there (issue
    // #40 item 9: it stopped short silently): once per stroke.
    if (warnings.empty() && rec.locked_snapped > 0 && !ts.warned_locked_snap) {
      ts.warned_locked_snap = true;
      warnings.push_back(coded_warning(
          "cut_stopped_short",
          cat("the blade (centre ", ts.tip.x(), ", ", ts.tip.y(), ", ", ts.tip.z(),
              " m) passes within the snap distance (", rec.locked_snap_reach * 1e3, " mm here) of ", rec.locked_snapped,
              " locked node(s) on the operational region's boundary: its crossings snap onto them and locked nodes "
              "are never cut, so the cut stops short of the interface; keep the blade farther inside "
              "s:operational{}, enlarge the region, or refine the mesh")));
    }
    for (const auto& w : warnings) {
      ev.warnings.push_back(w);
      s.warnings.push_back(cat("frame ", frame, " (t = ", t, " s), scalpel '", spec.name, "': ", w));
    }
    timer.reset();
    if (changed) {
      update_after_cut(rest, cm, rec);
      s.displacement = map_node_field(rec, s.displacement);
      const Eigen::Index old = s.forces.rows();
      s.forces.conservativeResize(cm.mesh.num_nodes(), 3);
      s.forces.bottomRows(s.forces.rows() - old).setZero();
      // Pieces cut free are held where they are (DESIGN.md invariants: the
      // rest stays exact; a floating piece would make the system singular).
      for (const DetachedPiece& piece : update_detached(cm, rec, s.displacement)) {
        ++cm.detached_pieces;
        ++ev.pieces_freed;
        ev.tets_freed += int(piece.tets.size());
        ev.nodes_freed += int(piece.nodes.size());
        const std::string pinned =
            piece.fixed_nodes > 0 ? cat(" (its ", piece.fixed_nodes, " fixed nodes lie at one point or on one line)")
                                  : std::string();
        const std::string w = coded_warning(
            "piece_cut_free",
            cat("piece of ", piece.tets.size(), " tets / ", piece.nodes.size(), " nodes (smallest node id ",
                piece.nodes.front(), ") cut free at frame ", frame, pinned, by_strokes(cm, piece),
                "; held at its displacement at separation (no rigid-body motion is simulated); loads and tool "
                "forces on it are ignored"));
        ev.warnings.push_back(w);
        s.warnings.push_back(cat("frame ", frame, " (t = ", t, " s), scalpel '", spec.name, "': ", w));
      }
      s.rebuild(cm, rec);
      // Grips the cut went through: each point onto a face of one side.
      const Eigen::MatrixX3d x = cm.mesh.nodes + s.displacement;
      for (tools::ToolState& other : s.tools) tools::rebind_grip(other, x, cm.surface);
      ts.cut_events++;
    }
    ev.nodes_after = cm.mesh.num_nodes(), ev.tets_after = cm.mesh.num_tets();
    ev.cut_ms = cut_ms, ev.rebuild_ms = timer.ms();
    if (changed) events.push_back(ev);
  }
  return events;
}

CuttingSummary cutting_summary(const mesh::TetMesh& mesh, const CutMesh* cm, const std::vector<CutEvent>& events) {
  CuttingSummary c;
  c.events = int(events.size());
  for (const CutEvent& e : events) c.nodes_added += e.nodes_added, c.faces_separated += e.faces_separated;
  c.nodes = mesh.num_nodes();
  c.tets = mesh.num_tets();
  c.faces_pending = cm ? int(cm->cut.pending.size()) : 0;
  c.components = count_components(mesh);
  std::vector<char> fixed(size_t(mesh.num_nodes()), 0);
  c.pieces = int(fem::anchor_parts(mesh, {}, fixed).parts.size());
  c.detached = cm ? cm->detached_pieces : 0;
  return c;
}

}  // namespace softcut::cut
