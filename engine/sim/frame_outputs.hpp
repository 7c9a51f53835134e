#pragma once
// The rendered frames of a run, or of a re-render (`softcut render`): each
// frame's scene goes to the frame writer with the paths of its images
// (frames/frame_NNNNNN.png, and depth_NNNNNN.png / labels_NNNNNN.png when
// asked), its camera is kept for camera.json, and at the end camera.json and
// the contact sheet are written (docs/rendering.md "Depth, labels and camera
// data").
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "core/json_text.hpp"
#include "render/frame_writer.hpp"
#include "render/scene.hpp"
#include "sim/frame_scene.hpp"
#include "sim/model.hpp"

namespace softcut {
class OutputBudget;
}

namespace softcut::sim {

struct FrameOutputOptions {
  bool depth = false, labels = false;
  Json legend = Json::array();  // camera.json labels.legend: [{id, name, kind}]
};

// The legend of label_legend(m) as JSON (camera.json, the render record).
Json legend_json(const LabelLegend& legend);

class FrameOutputs {
 public:
  // `writer` and `budget` (optional) outlive this.
  FrameOutputs(std::filesystem::path dir, FrameOutputOptions options, render::FrameWriter& writer,
               OutputBudget* budget = nullptr);

  // Queues frame `frame` (at `time` s) of `scene`; its camera goes to camera.json.
  void submit(render::Scene scene, int frame, double time);
  // Waits for the writer (rethrowing its failure), then writes camera.json
  // and, with `sheet`, contact_sheet.png. Idempotent.
  void finish(bool sheet);

  int submitted() const { return int(frames_.size()); }
  const std::vector<std::filesystem::path>& pngs() const { return pngs_; }
  const std::filesystem::path& dir() const { return dir_; }
  const FrameOutputOptions& options() const { return options_; }

 private:
  struct Frame {
    int frame;
    double time;
    render::Camera camera;
    int width, height;
  };

  std::filesystem::path dir_;
  FrameOutputOptions options_;
  render::FrameWriter& writer_;
  OutputBudget* budget_ = nullptr;
  std::vector<Frame> frames_;
  std::vector<std::filesystem::path> pngs_;
  bool finished_ = false;
};

// frames/<prefix>_NNNNNN.png below `dir` ("frame", "depth", "labels").
std::filesystem::path frame_image_path(const std::filesystem::path& dir, const char* prefix, int frame);

// camera.json's content for frames with these cameras (docs/rendering.md):
// OpenCV pinhole intrinsics, per frame world-to-camera R and t.
Json camera_json(int width, int height, double fov_y_deg, const FrameOutputOptions& o,
                 const std::vector<std::pair<int, double>>& frame_times, const std::vector<render::Camera>& cameras);

}  // namespace softcut::sim
