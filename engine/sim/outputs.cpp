#include "sim/outputs.hpp"

#include <pugixml.hpp>

#include <cstdio>
#include <exception>
#include <sstream>
#include <system_error>

#include "core/atomic_file.hpp"
#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/output_budget.hpp"
#include "core/timer.hpp"
#include "render/frame_writer.hpp"
#include "sim/frame_scene.hpp"
#include "sim/validity.hpp"

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

}  // namespace

Recorder::Recorder(const Model& m, fs::path dir, OutputBudget* budget)
    : dir_(dir.empty() ? m.spec.outputs.dir : std::move(dir)), budget_(budget), spec_render_(m.spec.outputs.render) {
  if (dir_.empty()) dir_ = fs::path("renders") / m.spec.name;
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_))
    fail("outputs: cannot create the output folder ", dir_.string(), ": ", ec ? ec.message() : "not a folder");
  // The folder is this run's: what an earlier run wrote there goes first, so
  // no stale frame, VTU or log is mistaken for this run's. Other files stay.
  clear_earlier_outputs(dir_);
  if (m.spec.outputs.vtu) make_folder_below(dir_, "vtu", "outputs");
  if (m.spec.outputs.csv) csv_.emplace(dir_, "displacements.csv", "frame,time,node,ux,uy,uz\n", budget_);
  if (!m.spec.tools.empty()) tools_.emplace(dir_, "tools.csv", kToolLogHeader, budget_);
  if (m.spec.outputs.csv) validity_.emplace(dir_, "validity.csv", kValidityLogHeader, budget_);
  if (wants_render_record(m)) record_ = std::make_unique<RenderRecordWriter>(dir_, render_record_meta(m), budget_);
  const LabelLegend legend = label_legend(m);
  if (m.spec.outputs.render.labels && legend.entries.size() > 255)
    fail("outputs: label images hold 255 ids; this scenario needs ", legend.entries.size(),
         " (materials, the cut surface and tools): use fewer s:material calls or tools, or no labels");
  legend_ = legend_json(legend);
}

void Recorder::set_frame_writer(render::FrameWriter* w) {
  writer_ = w;
  frame_outputs_.reset();
  if (!w) return;
  const RenderSettings& rs = spec_render_;
  frame_outputs_.emplace(dir_, FrameOutputOptions{rs.depth, rs.labels, legend_}, *w, budget_);
}

Recorder::~Recorder() = default;

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
    csv_->write(rows);
  }
  if (tools_) tools_->write(tool_log_rows(m, s));
  if (validity_) validity_->write(validity_log_row(s));
  tool_stats_.add(m, s);
  if (m.spec.outputs.vtu && s.frame % m.spec.outputs.vtu_every == 0) {
    const std::uintmax_t bytes = write_vtu(dir_ / "vtu" / vtu_name(s.frame), m, s);
    if (budget_) budget_->charge(bytes, "vtu/" + vtu_name(s.frame));
    vtu_frames_.emplace_back(s.frame, s.time);
  }
  const RenderSettings& rs = m.spec.outputs.render;
  if (rs.enabled && s.frame % rs.every == 0 && (frame_outputs_ || record_)) {
    Timer timer;
    const mesh::TetMesh& mesh = current_mesh(m, s);
    const Eigen::MatrixX3d x = deformed_positions(m, s);
    const render::SceneContent content = scene_content(m, s);
    const render::RenderSettings settings = render_settings(m, s);
    if (record_) record_->add(s.frame, s.time, mesh, x, content, settings.camera);
    if (frame_outputs_) {
      frame_outputs_->submit(extractor_.extract(mesh, x, content, settings), s.frame, s.time);
      rendered_++;
    }
    render_ms_.add(timer.ms());
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
  if (frame_outputs_) try {
      frame_outputs_->finish(m.spec.outputs.render.contact_sheet && r.reason != ExitReason::error);
    } catch (const std::exception& e) {
      render_failure = std::current_exception();
      if (r.reason != ExitReason::error) r.reason = ExitReason::error, r.message = e.what();
    }
  // A log that cannot be finished (a full disk, a file-size limit) makes the
  // run an error, but the summary is still written, saying so.
  std::exception_ptr write_failure;
  const auto attempt = [&](auto&& finish_one) {
    try {
      finish_one();
    } catch (const std::exception& e) {
      if (!write_failure) write_failure = std::current_exception();
      if (r.reason != ExitReason::error) r.reason = ExitReason::error, r.message = e.what();
    }
  };
  if (record_) attempt([&] { record_->finish(); });
  if (csv_) attempt([&] { csv_->finish(); });
  if (tools_) attempt([&] { tools_->finish(); });
  if (validity_) attempt([&] { validity_->finish(); });
  if (m.spec.outputs.vtu) attempt([&] {
    // ParaView's collection of the frames, by pugixml (names and numbers escaped as XML needs).
    pugi::xml_document doc;
    pugi::xml_node decl = doc.append_child(pugi::node_declaration);
    decl.append_attribute("version") = "1.0";
    pugi::xml_node vtk = doc.append_child("VTKFile");
    vtk.append_attribute("type") = "Collection";
    vtk.append_attribute("version") = "0.1";
    vtk.append_attribute("byte_order") = "LittleEndian";
    pugi::xml_node collection = vtk.append_child("Collection");
    for (const auto& [frame, time] : vtu_frames_) {
      pugi::xml_node d = collection.append_child("DataSet");
      d.append_attribute("timestep") = num(time, "%.9g").c_str();
      d.append_attribute("part") = 0;
      d.append_attribute("file") = ("vtu/" + vtu_name(frame)).c_str();
    }
    std::ostringstream pvd;
    doc.save(pvd, "  ", pugi::format_indent, pugi::encoding_utf8);
    if (budget_) budget_->charge(pvd.str().size(), "series.pvd");
    write_file_atomic(dir_ / "series.pvd", pvd.str());
  });
  write_file_atomic(dir_ / "summary.json", summary_json(m, s, r, this));
  if (render_failure) std::rethrow_exception(render_failure);
  if (write_failure) std::rethrow_exception(write_failure);
}

}  // namespace softcut::sim
