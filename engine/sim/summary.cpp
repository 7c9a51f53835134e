#include "sim/summary.hpp"

#include <Eigen/Core>
#include <set>

#include "core/json_text.hpp"
#include "core/output_budget.hpp"
#include "core/threads.hpp"
#include "render/frame_writer.hpp"
#include "sim/outputs.hpp"
#include "sim/validity.hpp"

namespace softcut::sim {

namespace {

// A time in ms (6 significant digits) and a plain number (15) as JSON.
Json jms(double v) { return json_number(v, 6); }
Json jnum(double v) { return json_number(v); }
Json jopt(const std::optional<double>& v) { return v ? jnum(*v) : Json(nullptr); }

// "cutting": totals and one entry per cut event (docs/summary-schema.md).
Json cutting_json(const Model& m, const State& s) {
  int scalpels = 0;
  for (const auto& t : s.tool_specs) scalpels += t.kind == tools::ToolSpec::Kind::scalpel;
  const mesh::TetMesh& cur = current_mesh(m, s);
  int nodes_added = 0, tets_split = 0;
  double worst = 180;
  for (const CutEvent& e : s.cut_events) {
    nodes_added += e.nodes_added, tets_split += e.tets_split;
    worst = std::min(worst, e.worst_dihedral_deg);
  }
  const DetachedCounts d = detached_counts(s);
  Json log = Json::array();
  for (const CutEvent& e : s.cut_events)
    log.push_back({{"frame", e.frame}, {"time_s", jnum(e.time)}, {"tool", e.tool}, {"tets_split", e.tets_split},
                   {"nodes_added", e.nodes_added}, {"edges_split", e.edges_split},
                   {"nodes_snapped", e.nodes_snapped}, {"faces_separated", e.faces_separated},
                   {"faces_pending", e.faces_pending}, {"nodes_after", e.nodes_after}, {"tets_after", e.tets_after},
                   {"worst_new_dihedral_deg", jnum(e.worst_new_dihedral_deg)},
                   {"worst_dihedral_deg", jnum(e.worst_dihedral_deg)}, {"cut_ms", jms(e.cut_ms)},
                   {"rebuild_ms", jms(e.rebuild_ms)}, {"cg_iterations_before", e.cg_iterations_before},
                   {"cg_iterations_after", e.cg_iterations_after}, {"pieces_freed", e.pieces_freed},
                   {"tets_freed", e.tets_freed}, {"nodes_freed", e.nodes_freed}, {"warnings", e.warnings}});
  return {{"scalpels", scalpels}, {"events", s.cut_events.size()}, {"nodes_added", nodes_added},
          {"tets_split", tets_split}, {"nodes", cur.num_nodes()}, {"tets", cur.num_tets()},
          {"components", cut::count_components(cur)}, {"detached_pieces", d.pieces},
          {"detached_tets", d.tets}, {"detached_nodes", d.nodes}, {"worst_dihedral_deg", jnum(worst)},
          {"log", std::move(log)}};
}

// The writer's side of rendering: where frames were drawn and what drawing,
// encoding and writing cost per frame (render_ms is the frame thread's part).
void add_render_work(Json& outputs, const Recorder* rec) {
  const render::FrameWriter* w = rec ? rec->frame_writer() : nullptr;
  if (!w) {
    outputs["render_mode"] = nullptr;
    outputs["render_work_ms"] = nullptr;
    return;
  }
  const render::FrameWriterStats st = w->stats();
  const double n = std::max(1, st.frames);
  outputs["render_mode"] = w->mode() == render::FrameWriter::Mode::worker ? "worker" : "inline";
  outputs["render_work_ms"] = {{"mean", jms(st.work.total_ms() / n)}, {"max", jms(st.max_work_ms)},
                               {"draw", jms((st.work.upload_ms + st.work.draw_ms + st.work.readback_ms) / n)},
                               {"encode", jms(st.work.encode_ms / n)}, {"write", jms(st.work.write_ms / n)},
                               {"depth_labels", jms(st.work.labels_ms() / n)}, {"video", jms(st.work.video_ms / n)}};
  outputs["video"] = w->video_bytes() > 0 ? Json("video.mp4") : Json(nullptr);
}

// "expectations": one entry per Scenario:expect, in declaration order.
Json expectations_json(const Model& m, const State& s) {
  Json list = Json::array();
  for (size_t i = 0; i < m.spec.expectations.size(); ++i) {
    const ExpectationSpec& e = m.spec.expectations[i];
    const ExpectationOutcome o = i < s.expectations.size() ? s.expectations[i] : ExpectationOutcome{};
    Json j = {{"name", e.name}, {"where", e.where}, {"at_s", jnum(e.at)}, {"kind", e.bounds ? "bounds" : "check"}};
    if (e.bounds) {
      j["measure"] = to_string(e.measure);
      j["component"] = to_string(e.component);
      j["nodes"] = m.expectation_nodes[i].size();
    }
    j["min"] = jopt(e.min);
    j["max"] = jopt(e.max);
    j["reached"] = o.reached;
    j["time_s"] = o.reached ? jnum(o.time) : Json(nullptr);
    j["value"] = jopt(o.value);
    j["pass"] = o.reached && o.ok;
    j["message"] = o.message;
    list.push_back(std::move(j));
  }
  return list;
}

}  // namespace

std::string summary_json(const Model& m, const State& s, const RunResult& r, const Recorder* rec) {
  const ScenarioSpec& sp = m.spec;
  const auto& c = m.partition.counts;
  Json j;
  j["schema"] = "softcut-summary/1";
  j["scenario"] = {{"name", sp.name}, {"source", sp.source.string()}, {"description", sp.description}};
  Json& versions = j["versions"] = {{"softcut", SOFTCUT_VERSION},
                                    {"eigen", std::to_string(EIGEN_WORLD_VERSION) + "." +
                                                  std::to_string(EIGEN_MAJOR_VERSION) + "." +
                                                  std::to_string(EIGEN_MINOR_VERSION)}};
  for (const auto& [k, v] : sp.versions) versions[k] = v;
  versions["build_type"] = SOFTCUT_BUILD_TYPE;
  j["command_line"] = sp.command_line;
  Json& params = j["params"] = Json::object();
  for (const auto& [k, v] : sp.params) params[k] = v;
  j["mesh"] = {{"nodes", m.mesh.num_nodes()}, {"tets", m.mesh.num_tets()}, {"surface_faces", m.surface.faces.rows()},
               {"surface_nodes", m.surface.nodes.size()}};
  j["partition"] = {{"operational_tets", c.operational_tets}, {"nonoperational_tets", c.nonoperational_tets},
                    {"operational_region_nodes", c.operational_region_nodes},
                    {"nonoperational_region_nodes", c.nonoperational_region_nodes},
                    {"nonoperational_surface_nodes", c.nonoperational_surface_nodes}, {"fixed", c.fixed},
                    {"operational", c.operational}, {"interface", c.interface}, {"surface", c.surface},
                    {"interior", c.interior}, {"unused", c.unused}};
  if (m.solver) {
    const backend::BackendChoice& bc = m.solver->backend();
    j["solver"] = {{"backend", to_string(bc.backend)}, {"requested", to_string(bc.requested)}, {"reason", bc.reason},
                   {"device", bc.device}, {"gpu_fp64", bc.gpu_fp64}, {"description", m.solver->name()},
                   {"cg_tolerance", jnum(sp.solver.cg_tolerance)}};
  } else {
    j["solver"] = nullptr;
  }
  Json& precompute = j["precompute_ms"] = Json::object();
  for (const auto& [k, v] : m.precompute_ms) precompute[k] = jms(v);
  // The precompute cache: hit or miss (and why), what a hit saved.
  if (const hybrid::CacheReport* pc = m.solver ? m.solver->precompute_cache() : nullptr) {
    j["precompute_cache"] = {{"hit", pc->hit}, {"key", pc->key}, {"file", pc->file}, {"miss_reason", pc->miss_reason},
                             {"load_ms", jms(pc->load_ms)}, {"saved_ms", jms(pc->saved_ms)},
                             {"write_ms", jms(pc->write_ms)}, {"bytes", jnum(pc->bytes)}, {"evicted", pc->evicted},
                             {"write_error", pc->write_error}};
  } else {
    j["precompute_cache"] = nullptr;
  }
  j["threads"] = {{"count", thread_policy().threads}, {"blas", thread_policy().blas_threads},
                  {"reason", thread_policy().reason}};
  // Columns of loaded surface nodes computed on demand (product and factor storage).
  if (const auto cs = m.solver ? m.solver->column_stats(s.solver_run) : std::nullopt) {
    j["columns"] = {{"hits", cs->hits}, {"first_touches", cs->first_touches}, {"waited", cs->waited},
                    {"prefetched", cs->prefetched}, {"evicted", cs->evicted}, {"cached_nodes", cs->cached_nodes},
                    {"bytes", jnum(cs->bytes)}, {"max_bytes", jnum(cs->max_bytes)},
                    {"first_touch_ms", jms(cs->first_touch_ms)}, {"prefetch_ms", jms(cs->prefetch_ms)}};
  } else {
    j["columns"] = nullptr;
  }
  const RunStatistics& st = s.stats;
  const double nf = st.frames > 0 ? double(st.frames) : 1.0;
  auto stage = [&](const StageStat& v) { return Json{{"mean", jms(v.sum / nf)}, {"max", jms(v.max)}}; };
  j["timeline"] = {{"duration_s", jnum(sp.timeline.duration)}, {"frame_rate_hz", jnum(sp.timeline.fps)},
                   {"frames_planned", m.num_frames}};
  j["run"] = {{"frames", st.frames}, {"last_frame", s.frame}, {"last_time_s", jnum(s.time)}, {"wall_s", jms(r.wall_s)},
              {"exit_reason", to_string(r.reason)}, {"interrupted", r.reason == ExitReason::interrupted},
              {"message", r.message}};
  // The run's bounds (--timeout, --max-output; 0: none) and what it wrote.
  j["limits"] = {{"timeout_s", jnum(sp.outputs.timeout_s)}, {"max_output_bytes", sp.outputs.max_bytes},
                 {"output_bytes", rec && rec->output_budget() ? rec->output_budget()->used() : 0}};
  j["stage_ms"] = {{"collision", stage(st.collision)}, {"cutting", stage(st.cutting)},
                   {"poke_drag", stage(st.poke_drag)}, {"operational_solve", stage(st.operational_solve)},
                   {"nonoperational_update", stage(st.nonoperational_update)}, {"total", stage(st.total)}};
  int implicit_tools = 0;
  for (const auto& t : s.tool_specs) implicit_tools += tools::is_implicit_spring(t);
  j["springs"] = {{"implicit_tools", implicit_tools}, {"frames", st.springs_frames},
                  {"ms", {{"mean", jms(st.springs_frames ? st.springs.sum / st.springs_frames : 0.0)},
                          {"max", jms(st.springs.max)}}},
                  {"compliance_builds", s.springs.builds}, {"compliance_ms_total", jms(s.springs.build_ms)},
                  {"grasped_nodes", s.springs.nodes.size()}};
  j["cg"] = {{"iterations_mean", jms(double(st.cg_iterations_total) / nf)}, {"iterations_max", st.cg_iterations_max},
             {"iterations_total", st.cg_iterations_total}, {"max_relative_residual", jnum(st.max_relative_residual)}};
  // Large deformation (DESIGN.md §1b): the Newton solves of nonlinear frames,
  // and what the linear law and the condensed region carried (sim/validity).
  constexpr double kDeg = 180.0 / M_PI;
  j["newton"] = {{"frames", st.newton_frames}, {"iterations_total", st.newton_iterations_total},
                 {"iterations_mean", jms(st.newton_frames ? double(st.newton_iterations_total) / st.newton_frames : 0.0)},
                 {"iterations_max", st.newton_iterations_max}, {"projected_steps", st.projected_steps},
                 {"floor_stops", st.floor_stops},
                 {"rotation_max_deg", jms(st.nonlinear_rotation_max * kDeg)},
                 {"strain_max", jnum(st.nonlinear_strain_max)}, {"inverted_tets_max", st.inverted_max}};
  j["validity"] = {{"linear_rotation_max_deg", jms(st.linear_rotation_max * kDeg)},
                   {"linear_rotation_frame", st.linear_rotation_frame},
                   {"linear_rotation_p99_max_deg", jms(st.linear_rotation_p99_max * kDeg)},
                   {"linear_rotation_p99_frame", st.linear_rotation_p99_frame},
                   {"linear_strain_max", jnum(st.linear_strain_max)}, {"linear_strain_frame", st.linear_strain_frame},
                   {"linear_strain_p99_max", jnum(st.linear_strain_p99_max)},
                   {"linear_strain_p99_frame", st.linear_strain_p99_frame},
                   {"condensed_rotation_max_deg", jms(st.condensed_rotation_max * kDeg)},
                   {"condensed_rotation_frame", st.condensed_rotation_frame},
                   {"condensed_rotation_p99_max_deg", jms(st.condensed_rotation_p99_max * kDeg)},
                   {"condensed_rotation_p99_frame", st.condensed_rotation_p99_frame},
                   {"log", rec && rec->writes_validity_log() ? Json("validity.csv") : Json(nullptr)},
                   {"bounds", {{"linear_rotation_deg", kLinearRotationBoundDeg}, {"linear_strain", kLinearStrainBound},
                               {"condensed_rotation_deg", kCondensedRotationBoundDeg}}}};
  // Frames written (with a writer that failed, fewer than were queued).
  const int rendered = !rec ? 0 : rec->frame_writer() ? rec->frame_writer()->stats().frames : rec->frames_rendered();
  Json& outputs = j["outputs"] = {
      {"log_nodes", m.log_nodes.size()},
      {"csv", sp.outputs.csv ? Json("displacements.csv") : Json(nullptr)},
      {"pvd", sp.outputs.vtu ? Json("series.pvd") : Json(nullptr)},
      {"tools_csv", rec && rec->writes_tool_log() ? Json("tools.csv") : Json(nullptr)},
      {"frames_rendered", rendered},
      {"render_ms",
       {{"mean", jms(rec && rec->frames_rendered() ? rec->render_frame_thread_ms().sum / rec->frames_rendered() : 0.0)},
        {"max", jms(rec ? rec->render_frame_thread_ms().max : 0.0)}}}};
  outputs["camera"] = rec && rec->writes_camera() ? Json("camera.json") : Json(nullptr);
  outputs["depth"] = rec && rec->writes_camera() && sp.outputs.render.depth;
  outputs["labels"] = rec && rec->writes_camera() && sp.outputs.render.labels;
  outputs["video"] = nullptr;
  outputs["render_record"] = rec && rec->writes_render_record() ? Json(kRenderRecordFile) : Json(nullptr);
  add_render_work(outputs, rec);
  j["tools"] = rec ? rec->tool_statistics().json() : Json::array();
  j["cutting"] = cutting_json(m, s);
  j["expectations"] = expectations_json(m, s);
  Json& metrics = j["metrics"] = Json::array();  // Frame:record (sim/control.hpp), first-recorded order
  for (const Metric& mt : s.metrics)
    metrics.push_back({{"name", mt.name}, {"value", jnum(mt.value)}, {"min", jnum(mt.min)}, {"max", jnum(mt.max)},
                       {"mean", jnum(mt.sum / mt.samples)}, {"samples", mt.samples}, {"frame", mt.frame},
                       {"time", jnum(mt.time)}});
  std::set<std::string> seen;
  Json& warnings = j["warnings"] = Json::array();
  for (const auto* list : {&m.warnings, &s.warnings})
    for (const auto& w : *list)
      if (seen.insert(w).second) warnings.push_back(w);
  return json_text(j);
}

}  // namespace softcut::sim
