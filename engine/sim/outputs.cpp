#include "sim/outputs.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <pugixml.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <sstream>
#include <system_error>

#include "core/atomic_file.hpp"
#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/output_budget.hpp"
#include "core/timer.hpp"
#include "render/contact_sheet.hpp"
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

}  // namespace

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

}  // namespace softcut::sim
