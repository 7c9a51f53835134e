#include "sim/outputs.hpp"

#include <Eigen/Core>
#include <cmath>
#include <exception>
#include <cstdio>
#include <set>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/atomic_file.hpp"
#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/threads.hpp"
#include "core/json_text.hpp"
#include "core/output_budget.hpp"
#include "render/contact_sheet.hpp"
#include "core/timer.hpp"
#include "render/frame_writer.hpp"
#include "sim/frame_scene.hpp"

namespace softcut::sim {

namespace fs = std::filesystem;

namespace {

std::string num(double v, const char* fmt = "%.9e") {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

std::string vtu_name(int frame) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "frame_%06d.vtu", frame);
  return buf;
}

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
                               {"encode", jms(st.work.encode_ms / n)}, {"write", jms(st.work.write_ms / n)}};
}

// True for the names softcut gives its own files in an output folder: the
// fixed ones in `fixed`, `<prefix>NNNNNN<ext>` (6 or more digits), and the
// temporary files write_file_atomic() makes for either (".<name>.<pid>.<n>.tmp").
bool softcut_output_name(std::string name, std::initializer_list<std::string_view> fixed, std::string_view prefix,
                         std::string_view ext) {
  if (name.size() > 5 && name[0] == '.' && name.ends_with(".tmp")) {
    name = name.substr(1, name.size() - 5);  // "<name>.<pid>.<n>"
    for (int k = 0; k < 2; ++k) {
      const size_t dot = name.find_last_of('.');
      if (dot == std::string::npos || dot + 1 == name.size() ||
          name.find_first_not_of("0123456789", dot + 1) != std::string::npos)
        return false;
      name.resize(dot);
    }
  }
  for (std::string_view f : fixed)
    if (name == f) return true;
  if (prefix.empty() || !name.starts_with(prefix) || !name.ends_with(ext)) return false;
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - ext.size());
  return digits.size() >= 6 && digits.find_first_not_of("0123456789") == std::string::npos;
}

// Unlinks (never follows) the entries of `dir` that softcut names; a
// subfolder that is a link or not a folder is left alone (the recorder
// refuses it later). Returns how many were removed.
int remove_softcut_files(const fs::path& dir, std::initializer_list<std::string_view> fixed, std::string_view prefix,
                         std::string_view ext) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(dir, ec))) return 0;
  int removed = 0;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::file_status st = it->symlink_status(ec);
    if (ec || fs::is_directory(st)) continue;
    if (softcut_output_name(it->path().filename().string(), fixed, prefix, ext) && fs::remove(it->path(), ec))
      ++removed;
  }
  return removed;
}

}  // namespace

int clear_earlier_outputs(const fs::path& dir) {
  int n = remove_softcut_files(dir, {"displacements.csv", "displacements.csv.partial", "summary.json", "series.pvd",
                                     "contact_sheet.png"},
                               {}, {});
  for (const auto& [sub, ext] : {std::pair{"frames", ".png"}, std::pair{"vtu", ".vtu"}}) {
    n += remove_softcut_files(dir / sub, {}, "frame_", ext);
    std::error_code ec;
    if (fs::is_directory(fs::symlink_status(dir / sub, ec))) fs::remove(dir / sub, ec);  // only when now empty
  }
  return n;
}

Recorder::Recorder(const Model& m, fs::path dir, OutputBudget* budget)
    : dir_(dir.empty() ? m.spec.outputs.dir : std::move(dir)), budget_(budget) {
  if (dir_.empty()) dir_ = fs::path("renders") / m.spec.name;
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_))
    fail("outputs: cannot create the output folder ", dir_.string(), ": ", ec ? ec.message() : "not a folder");
  // The folder is this run's: what an earlier run wrote there goes first, so
  // no stale frame, VTU or log is mistaken for this run's. Other files stay.
  clear_earlier_outputs(dir_);
  if (m.spec.outputs.vtu) make_folder_below(dir_, "vtu", "outputs");
  if (m.spec.outputs.csv) {
    csv_tmp_ = dir_ / "displacements.csv.partial";
    // A stale one (an earlier run killed) or a planted link goes first: the
    // file is then made new, never opened through a link.
    fs::remove(csv_tmp_, ec);
    const int fd = ::open(csv_tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0 || !(csv_ = ::fdopen(fd, "wb"))) {
      const int err = errno;
      if (fd >= 0) ::close(fd);
      fail("outputs: cannot write ", csv_tmp_.string(), " (", std::strerror(err), ")");
    }
    write_csv("frame,time,node,ux,uy,uz\n");
  }
}

Recorder::~Recorder() {
  if (!csv_) return;
  std::fclose(csv_);
  std::error_code ec;
  fs::remove(csv_tmp_, ec);
}

void Recorder::write_csv(std::string_view text) {
  if (budget_) budget_->charge(text.size(), "displacements.csv");
  if (std::fwrite(text.data(), 1, text.size(), csv_) != text.size())
    fail("outputs: writing ", csv_tmp_.string(), " failed (disk full?)");
}

void Recorder::record(const Model& m, const State& s) {
  if (finished_) fail("outputs: record() after finish()");
  if (csv_) {
    std::string rows;
    char buf[160];
    auto row = [&](int n) {
      const int len = std::snprintf(buf, sizeof buf, "%d,%.9e,%d,%.9e,%.9e,%.9e\n", s.frame, s.time, n,
                                    s.displacement(n, 0), s.displacement(n, 1), s.displacement(n, 2));
      rows.append(buf, std::size_t(len));
    };
    for (int n : m.log_nodes) row(n);
    // Nodes made by cutting (ids after the rest mesh's), every frame they exist.
    for (int n = m.mesh.num_nodes(); n < s.displacement.rows(); ++n) row(n);
    write_csv(rows);
  }
  if (m.spec.outputs.vtu && s.frame % m.spec.outputs.vtu_every == 0) {
    const std::uintmax_t bytes = write_vtu(dir_ / "vtu" / vtu_name(s.frame), m, s);
    if (budget_) budget_->charge(bytes, "vtu/" + vtu_name(s.frame));
    vtu_frames_.emplace_back(s.frame, s.time);
  }
  const RenderSettings& rs = m.spec.outputs.render;
  if (writer_ && rs.enabled && s.frame % rs.every == 0) {
    if (rendered_ == 0) make_folder_below(dir_, "frames", "outputs");
    Timer timer;
    frame_pngs_.push_back(frame_png_path(dir_, s.frame));
    writer_->submit(extractor_.extract(current_mesh(m, s), deformed_positions(m, s), scene_content(m, s),
                                       render_settings(m, s)),
                    frame_pngs_.back());
    render_ms_.add(timer.ms());
    rendered_++;
  }
  frames_++;
}

void Recorder::finish(const Model& m, const State& s, const RunResult& run_result) {
  if (finished_) return;
  finished_ = true;
  // Frames still being drawn come first. A failure there (GL error, full
  // disk) makes the run an error, but the summary is still written, saying so.
  RunResult r = run_result;
  std::exception_ptr render_failure;
  if (writer_) try {
      writer_->finish();
    } catch (const std::exception& e) {
      render_failure = std::current_exception();
      if (r.reason != ExitReason::error) r.reason = ExitReason::error, r.message = e.what();
    }
  if (csv_) {
    const bool ok = std::fflush(csv_) == 0 && !std::ferror(csv_);
    std::fclose(csv_);
    csv_ = nullptr;
    std::error_code ec;
    if (!ok) {
      fs::remove(csv_tmp_, ec);
      fail("outputs: writing ", csv_tmp_.string(), " failed (disk full?)");
    }
    fs::rename(csv_tmp_, dir_ / "displacements.csv", ec);
    if (ec) fail("outputs: cannot rename ", csv_tmp_.string(), " to displacements.csv: ", ec.message());
  }
  if (m.spec.outputs.vtu) {
    std::string pvd =
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        "  <Collection>\n";
    for (const auto& [frame, time] : vtu_frames_)
      pvd += "    <DataSet timestep=\"" + num(time, "%.9g") + "\" part=\"0\" file=\"vtu/" + vtu_name(frame) + "\"/>\n";
    pvd += "  </Collection>\n</VTKFile>\n";
    if (budget_) budget_->charge(pvd.size(), "series.pvd");
    write_file_atomic(dir_ / "series.pvd", pvd);
  }
  if (rendered_ > 0 && m.spec.outputs.render.contact_sheet && r.reason != ExitReason::error) {
    // At most ~24 tiles: a quick look at the whole run.
    const size_t stride = size_t(std::max(1, (rendered_ + 23) / 24));
    std::vector<fs::path> picked;
    for (size_t i = 0; i < frame_pngs_.size(); i += stride) picked.push_back(frame_pngs_[i]);
    render::write_png(dir_ / "contact_sheet.png", render::contact_sheet(picked));
    std::error_code ec;
    const std::uintmax_t bytes = fs::file_size(dir_ / "contact_sheet.png", ec);
    if (budget_ && !ec) budget_->charge(bytes, "contact_sheet.png");
  }
  write_file_atomic(dir_ / "summary.json", summary_json(m, s, r, this));
  if (render_failure) std::rethrow_exception(render_failure);
}

namespace {

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
  // Frames written (with a writer that failed, fewer than were queued).
  const int rendered = !rec ? 0 : rec->frame_writer() ? rec->frame_writer()->stats().frames : rec->frames_rendered();
  Json& outputs = j["outputs"] = {
      {"log_nodes", m.log_nodes.size()},
      {"csv", sp.outputs.csv ? Json("displacements.csv") : Json(nullptr)},
      {"pvd", sp.outputs.vtu ? Json("series.pvd") : Json(nullptr)},
      {"frames_rendered", rendered},
      {"render_ms",
       {{"mean", jms(rec && rec->frames_rendered() ? rec->render_frame_thread_ms().sum / rec->frames_rendered() : 0.0)},
        {"max", jms(rec ? rec->render_frame_thread_ms().max : 0.0)}}}};
  add_render_work(outputs, rec);
  j["cutting"] = cutting_json(m, s);
  j["expectations"] = expectations_json(m, s);
  std::set<std::string> seen;
  Json& warnings = j["warnings"] = Json::array();
  for (const auto* list : {&m.warnings, &s.warnings})
    for (const auto& w : *list)
      if (seen.insert(w).second) warnings.push_back(w);
  return json_text(j);
}

std::uintmax_t write_vtu(const fs::path& path, const Model& m, const State& s) {
  const mesh::TetMesh& mesh = current_mesh(m, s);
  const Eigen::MatrixX3d& u = s.displacement;
  const std::vector<char>& operational = s.cut ? s.cut->operational_tet : m.partition.operational_tet;
  return write_file_atomic(path, [&](std::ostream& os) {
    char buf[128];
    os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
       << "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" << mesh.num_nodes() << "\" NumberOfCells=\""
       << mesh.num_tets() << "\">\n";
    os << "      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      std::snprintf(buf, sizeof buf, "%.9e %.9e %.9e\n", mesh.nodes(n, 0), mesh.nodes(n, 1), mesh.nodes(n, 2));
      os << buf;
    }
    os << "        </DataArray>\n      </Points>\n      <PointData Vectors=\"displacement\">\n"
       << "        <DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      std::snprintf(buf, sizeof buf, "%.9e %.9e %.9e\n", u(n, 0), u(n, 1), u(n, 2));
      os << buf;
    }
    os << "        </DataArray>\n        <DataArray type=\"Int32\" Name=\"node_set\" format=\"ascii\">\n";
    for (int n = 0; n < mesh.num_nodes(); ++n) os << int(node_set(m, s, n)) << '\n';
    os << "        </DataArray>\n      </PointData>\n      <CellData Scalars=\"label\">\n"
       << "        <DataArray type=\"Int32\" Name=\"label\" format=\"ascii\">\n";
    for (int t = 0; t < mesh.num_tets(); ++t) os << mesh.labels(t) << '\n';
    os << "        </DataArray>\n        <DataArray type=\"Int32\" Name=\"operational\" format=\"ascii\">\n";
    for (int t = 0; t < mesh.num_tets(); ++t) os << int(operational[size_t(t)]) << '\n';
    os << "        </DataArray>\n      </CellData>\n      <Cells>\n"
       << "        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
    for (int t = 0; t < mesh.num_tets(); ++t)
      os << mesh.tets(t, 0) << ' ' << mesh.tets(t, 1) << ' ' << mesh.tets(t, 2) << ' ' << mesh.tets(t, 3) << '\n';
    os << "        </DataArray>\n        <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
    for (int t = 0; t < mesh.num_tets(); ++t) os << 4 * (t + 1) << '\n';
    os << "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (int t = 0; t < mesh.num_tets(); ++t) os << "10\n";
    os << "        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  });
}

}  // namespace softcut::sim
