#include "sim/frame_outputs.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/atomic_file.hpp"
#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/output_budget.hpp"
#include "render/contact_sheet.hpp"
#include "render/gray_png.hpp"

namespace softcut::sim {

namespace fs = std::filesystem;

fs::path frame_image_path(const fs::path& dir, const char* prefix, int frame) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%s_%06d.png", prefix, frame);
  return dir / "frames" / buf;
}

Json legend_json(const LabelLegend& legend) {
  Json list = Json::array();
  list.push_back({{"id", 0}, {"name", "background"}, {"kind", "background"}});
  for (const LabelLegend::Entry& e : legend.entries) list.push_back({{"id", e.id}, {"name", e.name}, {"kind", e.kind}});
  return list;
}

Json camera_json(int width, int height, double fov_y_deg, const FrameOutputOptions& o,
                 const std::vector<std::pair<int, double>>& frame_times, const std::vector<render::Camera>& cameras) {
  // OpenCV's pinhole: x right, y down, z forward; pixel (u, v) centres at
  // integer coordinates from the top-left pixel's. GL's eye space has y up
  // and looks down -z: the same axes with y and z flipped.
  const double f = 0.5 * height / std::tan(0.5 * fov_y_deg * std::numbers::pi / 180.0);
  Json j;
  j["schema"] = "softcut-camera/1";
  j["convention"] =
      "OpenCV pinhole: camera x right, y down, z forward (into the scene), metres; X_cam = R X_world + t; "
      "u = fx X_cam/Z_cam + cx, v = fy Y_cam/Z_cam + cy, with pixel (u, v) centres at integer coordinates from the "
      "top-left pixel's centre";
  j["width"] = width, j["height"] = height;
  j["fx"] = json_number(f), j["fy"] = json_number(f);
  j["cx"] = json_number(0.5 * width - 0.5), j["cy"] = json_number(0.5 * height - 0.5);
  j["fov_y_deg"] = json_number(fov_y_deg);
  j["images"] = {{"rgb", "frames/frame_%06d.png"}};
  if (o.depth)
    j["depth"] = {{"images", "frames/depth_%06d.png"}, {"scale", render::kDepthUnitsPerMm},
                  {"meaning", "16-bit: Z_cam in millimetres times scale (Z_cam = value / scale / 1000 m); "
                              "0: background; 65535: farther than 6553.5 mm"}};
  if (o.labels)
    j["labels"] = {{"images", "frames/labels_%06d.png"},
                   {"meaning", "8-bit: the id of the surface each pixel's centre sees first (no antialiasing)"},
                   {"legend", o.legend}};
  Json frames = Json::array();
  const Eigen::Matrix3d flip = Eigen::Vector3d(1, -1, -1).asDiagonal();
  for (std::size_t i = 0; i < cameras.size() && i < frame_times.size(); ++i) {
    const Eigen::Matrix3d R = flip * cameras[i].view.topLeftCorner<3, 3>();
    const Eigen::Vector3d t = flip * cameras[i].view.topRightCorner<3, 1>();
    Json rows = Json::array();
    for (int r = 0; r < 3; ++r) rows.push_back({json_number(R(r, 0)), json_number(R(r, 1)), json_number(R(r, 2))});
    frames.push_back({{"frame", frame_times[i].first}, {"time_s", json_number(frame_times[i].second)}, {"R", rows},
                      {"t", {json_number(t.x()), json_number(t.y()), json_number(t.z())}}});
  }
  j["frames"] = std::move(frames);
  return j;
}

FrameOutputs::FrameOutputs(fs::path dir, FrameOutputOptions options, render::FrameWriter& writer, OutputBudget* budget)
    : dir_(std::move(dir)), options_(std::move(options)), writer_(writer), budget_(budget) {}

void FrameOutputs::submit(render::Scene scene, int frame, double time) {
  if (finished_) fail("outputs: a frame after the frames were finished");
  if (frames_.empty()) make_folder_below(dir_, "frames", "outputs");
  if (!frames_.empty() && (scene.width != frames_.front().width || scene.height != frames_.front().height ||
                           scene.camera.fov_y_deg != frames_.front().camera.fov_y_deg))
    fail("outputs: frame ", frame, " changes the image size or field of view; camera.json holds one intrinsics");
  frames_.push_back({frame, time, scene.camera, scene.width, scene.height});
  render::FramePaths paths{frame_image_path(dir_, "frame", frame), {}, {}};
  if (options_.depth) paths.depth = frame_image_path(dir_, "depth", frame);
  if (options_.labels) paths.labels = frame_image_path(dir_, "labels", frame);
  pngs_.push_back(paths.rgb);
  writer_.submit(std::move(scene), std::move(paths));
}

void FrameOutputs::finish(bool sheet) {
  if (finished_) return;
  finished_ = true;
  writer_.finish();
  if (frames_.empty()) return;
  std::vector<std::pair<int, double>> times;
  std::vector<render::Camera> cameras;
  for (const Frame& f : frames_) times.emplace_back(f.frame, f.time), cameras.push_back(f.camera);
  const std::string text =
      json_text(camera_json(frames_.front().width, frames_.front().height, frames_.front().camera.fov_y_deg, options_,
                            times, cameras));
  if (budget_) budget_->charge(text.size(), "camera.json");
  write_file_atomic(dir_ / "camera.json", text);
  if (sheet) {
    // At most ~24 tiles: a quick look at the whole run.
    const size_t stride = size_t(std::max<size_t>(1, (pngs_.size() + 23) / 24));
    std::vector<fs::path> picked;
    for (size_t i = 0; i < pngs_.size(); i += stride) picked.push_back(pngs_[i]);
    render::write_png(dir_ / "contact_sheet.png", render::contact_sheet(picked));
    std::error_code ec;
    const std::uintmax_t bytes = fs::file_size(dir_ / "contact_sheet.png", ec);
    if (budget_ && !ec) budget_->charge(bytes, "contact_sheet.png");
  }
}

}  // namespace softcut::sim
