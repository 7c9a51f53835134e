#include "sim/cutting.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "core/warning.hpp"
#include "cut/cutter.hpp"
#include "sim/model.hpp"

namespace softcut::sim {

const mesh::TetMesh& current_mesh(const Model& m, const State& s) { return s.cut ? s.cut->mesh : m.mesh; }
const mesh::Surface& current_surface(const Model& m, const State& s) { return s.cut ? s.cut->surface : m.surface; }

bool is_fixed_node(const Model& m, const State& s, int n) {
  if (s.cut) return s.cut->node_fixed[size_t(n)] != 0;
  return m.partition.node_set[size_t(n)] == hybrid::NodeSet::fixed;
}

bool is_held_node(const State& s, int n) { return s.cut && cut::is_held(*s.cut, n); }

hybrid::NodeSet node_set(const Model& m, const State& s, int n) {
  if (n < m.mesh.num_nodes()) return m.partition.node_set[size_t(n)];
  return is_fixed_node(m, s, n) ? hybrid::NodeSet::fixed : hybrid::NodeSet::operational;
}

backend::CutBody cut_body(const CutMesh& cm, const cut::CutRecord* rec) {
  backend::CutBody body{cm.mesh, cm.tet_material, cm.operational_tet, cm.node_fixed, -1, {}};
  if (rec) {
    body.nodes_before = rec->nodes_before;
    body.carry = [rec](const Eigen::MatrixX3d& u) { return cut::map_node_field(*rec, u); };
  }
  return body;
}

std::vector<CutEvent> cut_stage(const Model& m, State& s, int frame, double t) {
  const cut::RestBody rest{m.mesh, m.surface, m.tet_material, m.partition.operational_tet, m.partition.fixed,
                           m.partition.interface};
  cut::StageFrame f{.frame = frame,
                    .t = t,
                    .t_prev = m.frame_time(frame - 1),
                    .dt = m.dt,
                    .options = {m.spec.cutting.snap_fraction, m.spec.cutting.min_dihedral_deg},
                    .cut = s.cut,
                    .specs = s.tool_specs,
                    .tools = s.tools,
                    .displacement = s.displacement,
                    .forces = s.forces,
                    .warnings = s.warnings,
                    .cg_iterations_before = s.last_cg_iterations,
                    .rebuild = [&](const CutMesh& cm, const cut::CutRecord& rec) {
                      m.solver->apply_cut(cut_body(cm, &rec), s.solver_run);
                    }};
  std::vector<CutEvent> events = cut::cut_stage(rest, f);
  s.cut_events.insert(s.cut_events.end(), events.begin(), events.end());
  return events;
}

void drop_loads_on_held(State& s, int frame, double t) {
  if (!s.cut || s.cut->detached_pieces == 0) return;
  CutMesh& cm = *s.cut;
  auto warn_once = [&](const std::string& key, const std::string& what) {
    if (std::find(cm.ignored_on_held.begin(), cm.ignored_on_held.end(), key) != cm.ignored_on_held.end()) return;
    cm.ignored_on_held.push_back(key);
    s.warnings.push_back(coded_warning("force_on_held_piece",
                                       cat("frame ", frame, " (t = ", t, " s), ", what,
                                           " acts on a piece cut free; its force there is ignored (the piece is held)")));
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
  if (s.cut) cut::hold_detached(*s.cut, s.displacement);
}

DetachedCounts detached_counts(const State& s) { return s.cut ? cut::detached_counts(*s.cut) : DetachedCounts{}; }

CuttingSummary cutting_summary(const Model& m, const State& s) {
  return cut::cutting_summary(current_mesh(m, s), s.cut.get(), s.cut_events);
}

}  // namespace softcut::sim
