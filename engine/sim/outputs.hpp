#pragma once
// Run outputs (DESIGN.md §5, docs/outputs.md, docs/summary-schema.md):
// displacements.csv streamed to a temporary file and renamed at the end,
// optional VTU per frame + series.pvd, summary.json; all atomic.
#include <Eigen/Core>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sim/model.hpp"
#include "sim/run.hpp"

namespace softcut::render {
class Renderer;
}

namespace softcut::sim {

class Recorder {
 public:
  // Creates `dir` (default: m.spec.outputs.dir) and opens the temporary CSV.
  explicit Recorder(const Model& m, std::filesystem::path dir = {});
  ~Recorder();  // removes the temporary CSV when finish() was never called
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // With a renderer (made by the application on its EGL context) and
  // outputs.render.enabled, record() also writes frames/frame_NNNNNN.png.
  void set_renderer(render::Renderer* r) { renderer_ = r; }

  // Appends frame s.frame: CSV rows `frame,time,node,ux,uy,uz` for the log
  // nodes (%.9e), vtu/frame_NNNNNN.vtu and frames/frame_NNNNNN.png when due.
  void record(const Model& m, const State& s);
  // Flushes, renames the CSV into place, writes series.pvd and summary.json.
  void finish(const Model& m, const State& s, const RunResult& r);

  const std::filesystem::path& dir() const { return dir_; }
  int frames_recorded() const { return frames_; }
  const StageStat& render_ms() const { return render_ms_; }  // per rendered frame
  int frames_rendered() const { return rendered_; }

 private:
  std::filesystem::path dir_, csv_tmp_;
  std::ofstream csv_;
  std::vector<std::pair<int, double>> vtu_frames_;  // (frame, time) written
  int frames_ = 0, rendered_ = 0;
  StageStat render_ms_;
  render::Renderer* renderer_ = nullptr;
  bool finished_ = false;
};

// summary.json text (schema in docs/summary-schema.md); `rec` adds the
// rendering statistics when given.
std::string summary_json(const Model& m, const State& s, const RunResult& r, const Recorder* rec = nullptr);

// VTU (XML, ascii) of the current (possibly cut) mesh with point data
// "displacement" (nnode x 3) and "node_set", cell data "label" and
// "operational"; atomic.
void write_vtu(const std::filesystem::path& path, const Model& m, const State& s);

}  // namespace softcut::sim
