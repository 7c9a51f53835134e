#include "sim/step.hpp"

#include <algorithm>
#include <cmath>

#include "core/timer.hpp"
#include "sim/validity.hpp"
#include "tools/springs.hpp"

namespace softcut::sim {

double load_per_node(const ActiveLoad& l, double t) {
  const double mag = tools::evaluate(l.spec.magnitude, t) * l.scale;
  return l.spec.per_node ? mag : mag / double(l.nodes.size());
}

Eigen::MatrixX3d load_forces(const Model& m, const State& s, double t) {
  Eigen::MatrixX3d f = Eigen::MatrixX3d::Zero(current_mesh(m, s).num_nodes(), 3);
  for (const auto& l : s.loads) {
    if (!l.enabled) continue;
    const double per_node = load_per_node(l, t);
    if (!std::isfinite(per_node))
      fail(l.spec.where.empty() ? "" : l.spec.where + ": ", "load '", l.spec.name, "': magnitude is not finite at t = ",
           t, " s");
    for (size_t k = 0; k < l.nodes.size(); ++k) f.row(l.nodes[k]) += per_node * l.directions.row(Eigen::Index(k));
  }
  return f;
}

namespace {

// The grasper springs' view of this frame's system (tools/springs.hpp).
tools::SpringSystem spring_system(const Model& m, State& s) {
  tools::SpringSystem sys;
  sys.mesh = &current_mesh(m, s);
  sys.fixed = [&m, &s](int n) { return is_fixed_node(m, s, n); };
  if (s.cut)
    sys.held = [&s](int n) -> Eigen::Vector3d {
      if (!is_held_node(s, n)) return Eigen::Vector3d::Zero();
      return s.cut->held_displacement.row(n).transpose();
    };
  sys.generation = m.solver->system_generation(s.solver_run);
  sys.unit_responses = [&m, &s](const std::vector<int>& nodes, Eigen::MatrixXd& out) {
    m.solver->unit_responses(nodes, s.solver_run, out);
  };
  return sys;
}

}  // namespace

void step(const Model& m, State& s) {
  Timer total;
  const int frame = s.frame + 1;
  const double t = m.frame_time(frame);
  FrameTimings ft;

  // Tools on the current deformed surface (last frame's displacements).
  Timer timer;
  bool any_tool = false;
  for (const auto& spec : s.tool_specs) any_tool |= spec.enabled;
  if (s.tools.size() != s.tool_specs.size()) s.tools.resize(s.tool_specs.size());
  if (any_tool || !s.tools.empty()) {
    // After a cut the current mesh's boundary (with the cut faces) is touched.
    const mesh::TetMesh& mesh = current_mesh(m, s);
    const mesh::Surface& surface = current_surface(m, s);
    const Eigen::MatrixX3d x = deformed_positions(m, s);
    const Eigen::MatrixX3d normals = any_tool ? mesh::vertex_normals(mesh, surface, x) : Eigen::MatrixX3d();
    const tools::ContactSurface contact{x, surface, normals};
    for (size_t k = 0; k < s.tools.size(); ++k) tools::update_tool(s.tool_specs[k], s.tools[k], t, contact);
  }
  ft.collision = timer.ms();

  // Cutting: scalpels at or above their pressure cut what they swept since
  // the last frame; the mesh, the solver's system and the fields grow.
  timer.reset();
  std::vector<CutEvent> cuts = cut_stage(m, s, frame, t);
  ft.cutting = timer.ms();

  // Poke / drag: scripted loads plus explicit tool forces (fixed nodes take
  // none); implicit springs are solved after the elastic solve.
  timer.reset();
  s.forces = load_forces(m, s, t);
  for (size_t i = 0; i < s.tools.size(); ++i) {
    if (i < s.tool_specs.size() && tools::is_implicit_spring(s.tool_specs[i])) continue;
    const tools::ToolState& ts = s.tools[i];
    for (size_t k = 0; k < ts.nodes.size(); ++k)
      if (!is_fixed_node(m, s, ts.nodes[k]) && k < ts.forces.size()) s.forces.row(ts.nodes[k]) += ts.forces[k].transpose();
  }
  drop_loads_on_held(s, frame, t);  // pieces cut free take no load
  double poke_drag_ms = timer.ms();

  // A nonlinear model takes the graspers inside its Newton solve; a linear
  // one superposes them on the solve exactly afterwards.
  backend::SolveStats st;
  backend::FrameInput in;
  const Eigen::MatrixX3d prescribed = prescribed_displacements(m, t, s.forces.rows());
  if (prescribed.size() > 0) in.prescribed = &prescribed;
  const tools::SpringSystem springs_sys = spring_system(m, s);
  fem::GripSprings grip;
  const bool inside = m.solver->nonlinear();
  timer.reset();
  bool springs = inside && tools::grip_springs(springs_sys, s.tool_specs, s.tools, s.springs, grip, frame) > 0;
  double springs_ms = timer.ms();
  if (springs) in.springs = &grip;
  m.solver->solve(s.forces, s.displacement, s.solver_run, st, in);
  timer.reset();
  if (inside) {
    if (springs) tools::grasper_forces(springs_sys, s.tool_specs, s.tools, s.displacement, s.forces);
  } else {
    springs = tools::solve_implicit_springs(springs_sys, s.tool_specs, s.tools, s.springs, s.displacement, s.forces,
                                            frame) > 0;
  }
  springs_ms += timer.ms();
  hold_detached(s);  // pieces cut free stay where they separated
  poke_drag_ms += springs_ms;
  if (!s.displacement.allFinite()) fail("frame ", frame, " (t = ", t, " s): the solve produced non-finite displacements");
  ft.poke_drag = poke_drag_ms + st.loads_ms;
  ft.operational_solve = st.operational_ms;
  ft.nonoperational_update = st.nonoperational_ms;
  ft.total = total.ms();

  s.frame = frame;
  s.time = t;
  s.last = ft;
  s.last_cg_iterations = st.cg_iterations;
  for (size_t k = s.cut_events.size() - cuts.size(); k < s.cut_events.size(); ++k)
    s.cut_events[k].cg_iterations_after = st.cg_iterations;
  RunStatistics& r = s.stats;
  r.frames++;
  r.collision.add(ft.collision), r.cutting.add(ft.cutting), r.poke_drag.add(ft.poke_drag);
  r.operational_solve.add(ft.operational_solve), r.nonoperational_update.add(ft.nonoperational_update);
  r.total.add(ft.total);
  if (springs) r.springs.add(springs_ms), r.springs_frames++;
  r.cg_iterations_total += st.cg_iterations;
  r.cg_iterations_max = std::max(r.cg_iterations_max, st.cg_iterations);
  r.max_relative_residual = std::max(r.max_relative_residual, st.relative_residual);
  if (st.newton) {
    r.newton_frames++;
    r.newton_iterations_total += st.newton_iterations;
    r.newton_iterations_max = std::max(r.newton_iterations_max, st.newton_iterations);
    r.projected_steps += st.projected_steps;
    r.floor_stops += st.at_floor;
    r.nonlinear_rotation_max = std::max(r.nonlinear_rotation_max, st.max_rotation);
    r.nonlinear_strain_max = std::max(r.nonlinear_strain_max, st.max_strain);
    r.inverted_max = std::max(r.inverted_max, st.inverted);
  }
  s.last_newton_iterations = st.newton ? st.newton_iterations : 0;
  const Validity& v = s.last_validity = measure_validity(m, s);
  const auto peak = [&](double value, double& max, int& at) {
    if (value > max) max = value, at = frame;
  };
  peak(v.linear_rotation, r.linear_rotation_max, r.linear_rotation_frame);
  peak(v.linear_strain, r.linear_strain_max, r.linear_strain_frame);
  peak(v.condensed_rotation, r.condensed_rotation_max, r.condensed_rotation_frame);
  peak(v.linear_rotation_p99, r.linear_rotation_p99_max, r.linear_rotation_p99_frame);
  peak(v.linear_strain_p99, r.linear_strain_p99_max, r.linear_strain_p99_frame);
  peak(v.condensed_rotation_p99, r.condensed_rotation_p99_max, r.condensed_rotation_p99_frame);
}

}  // namespace softcut::sim
