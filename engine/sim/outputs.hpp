#pragma once
// Run outputs (DESIGN.md §5, docs/outputs.md, docs/summary-schema.md): the
// Recorder writes displacements.csv (streamed to a temporary file and renamed
// at the end), optional VTU per frame + series.pvd, frames, summary.json; all
// atomic. The folder's rules, the summary and the VTU export have their own
// headers, included here for the Recorder's users.
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <filesystem>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "render/scene.hpp"
#include "sim/frame_outputs.hpp"
#include "sim/model.hpp"
#include "sim/output_folder.hpp"
#include "sim/render_record.hpp"
#include "sim/render_record_meta.hpp"
#include "sim/run.hpp"
#include "sim/streamed_file.hpp"
#include "sim/summary.hpp"
#include "sim/tool_log.hpp"
#include "sim/vtu_export.hpp"

namespace softcut {
class OutputBudget;
}
namespace softcut::render {
class FrameWriter;
}

namespace softcut::sim {

class Recorder {
 public:
  // Creates `dir` (default: m.spec.outputs.dir), clears what an earlier run
  // left there (clear_earlier_outputs) and opens the temporary CSV.
  // Its subfolders (frames/, vtu/) and every file in it are made without
  // following links: a symlink planted there is refused, never written through.
  // `budget` (optional, outlives the recorder) bounds the bytes written.
  explicit Recorder(const Model& m, std::filesystem::path dir = {}, OutputBudget* budget = nullptr);
  ~Recorder();  // removes the temporary CSV when finish() was never called
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // With a frame writer (made by the application on its EGL context) and
  // outputs.render.enabled, record() also queues frames/frame_NNNNNN.png
  // (and the depth and label images when asked, sim/frame_outputs.hpp);
  // finish() waits for the writer before camera.json and the contact sheet.
  void set_frame_writer(render::FrameWriter* w);

  // Appends frame s.frame: CSV rows `frame,time,node,ux,uy,uz` for the log
  // nodes (%.9e), a tools.csv row per tool (sim/tool_log.hpp),
  // vtu/frame_NNNNNN.vtu and frames/frame_NNNNNN.png when due.
  void record(const Model& m, const State& s);
  // Flushes, renames the CSVs into place, writes series.pvd and summary.json.
  void finish(const Model& m, const State& s, const RunResult& r);

  const std::filesystem::path& dir() const { return dir_; }
  int frames_recorded() const { return frames_; }
  // Per rendered frame, ms: scene extraction plus handing the scene to the
  // writer (with a worker writer the drawing and writing happen meanwhile,
  // see render::FrameWriter::stats()).
  const StageStat& render_frame_thread_ms() const { return render_ms_; }
  int frames_rendered() const { return rendered_; }
  const render::FrameWriter* frame_writer() const { return writer_; }
  const OutputBudget* output_budget() const { return budget_; }
  const ToolStatistics& tool_statistics() const { return tool_stats_; }
  bool writes_tool_log() const { return tools_.has_value(); }
  bool writes_validity_log() const { return validity_.has_value(); }
  bool writes_render_record() const { return record_ != nullptr; }
  bool writes_camera() const { return frame_outputs_ && frame_outputs_->submitted() > 0; }

 private:
  std::filesystem::path dir_;
  OutputBudget* budget_ = nullptr;
  std::optional<StreamedFile> csv_, tools_;  // displacements.csv; tools.csv (when the scenario has tools)
  std::optional<StreamedFile> validity_;     // validity.csv (with csv: the solve and validity per frame)
  ToolStatistics tool_stats_;
  RenderSettings spec_render_;
  Json legend_;                                      // of the label images
  std::vector<std::pair<int, double>> vtu_frames_;  // (frame, time) written
  std::optional<FrameOutputs> frame_outputs_;        // with a frame writer
  std::unique_ptr<RenderRecordWriter> record_;       // render_record.bin
  int frames_ = 0, rendered_ = 0;
  StageStat render_ms_;
  render::FrameWriter* writer_ = nullptr;
  render::SceneExtractor extractor_;
  bool finished_ = false;
};

}  // namespace softcut::sim
