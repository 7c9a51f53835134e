// softcut render RUNDIR [--out DIR] [--eye X,Y,Z --target X,Y,Z] [--fov D] [--size WxH] [--msaa N]
//                [--style S] [--depth] [--labels] [--video]: redraws a finished run's frames from its
// render_record.bin, without simulating it again.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <tuple>

#include "app/commands.hpp"
#include "app/option_values.hpp"
#include "app/options.hpp"
#include "app/run_support.hpp"
#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/output_budget.hpp"
#include "core/timer.hpp"
#include "core/watchdog.hpp"
#include "gl/egl_context.hpp"
#include "render/frame_writer.hpp"
#include "render/video_encoder.hpp"
#include "sim/frame_outputs.hpp"
#include "sim/frame_scene.hpp"
#include "sim/output_folder.hpp"
#include "sim/render_record.hpp"
#include "sim/render_record_meta.hpp"

namespace softcut::app {

namespace fs = std::filesystem;

namespace {

const char* kRenderAbout =
    "Redraws the frames of a finished run from its render_record.bin (written by softcut run when it\n"
    "renders; --record forces it) without simulating it again: the authoring loop for framing a shot.\n"
    "With the camera and size unchanged the frames are the run's, byte for byte. Writes\n"
    "DIR/frames/frame_NNNNNN.png (and depth_/labels_ images), DIR/camera.json, DIR/contact_sheet.png\n"
    "and, with --video, DIR/video.mp4 (default DIR: RUNDIR/rendered).";

const char* kRenderFooter =
    "The record is read as untrusted input: every count and size is checked before anything is made\n"
    "from it (--max-bytes bounds the file). Exit status: 0 done, 1 an error, 2 usage, 124 --timeout.";

Eigen::Vector3d parse_vec3(const std::string& text, const char* option) {
  Eigen::Vector3d v;
  std::size_t at = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t end = k < 2 ? text.find(',', at) : text.size();
    std::size_t used = 0;
    double x = 0;
    try {
      x = std::stod(text.substr(at, end == std::string::npos ? std::string::npos : end - at), &used);
    } catch (...) {
      used = 0;
    }
    if (end == std::string::npos || used == 0 || used != end - at || !std::isfinite(x))
      usage_fail(option, " ", text, ": expected X,Y,Z in metres (e.g. 0.1,-0.2,0.15)");
    v[k] = x;
    at = end + 1;
  }
  return v;
}

}  // namespace

int cmd_render(const Args& args) {
  Options o("softcut render", kRenderAbout, kRenderFooter);
  CLI::App& app = o.app();
  std::vector<std::string> dirs;
  std::string out_dir, eye, target, up, fov, style;
  FrameSize size;
  int msaa = 0, max_frames = -1;
  double limit_s = 3600;
  std::uint64_t limit_bytes = std::uint64_t(8) << 30;
  bool depth = false, labels = false, video = false, quiet = false;
  app.add_option("rundir", dirs, "the run's output folder (holding render_record.bin)")->type_name("RUNDIR");
  app.add_option("--out", out_dir, "where the frames go (default RUNDIR/rendered; not RUNDIR itself)")->type_name("DIR");
  app.add_option("--eye", eye, "camera position, m (with --target: a fixed camera instead of the run's)")
      ->type_name("X,Y,Z");
  app.add_option("--target", target, "point looked at, m (with --eye)")->type_name("X,Y,Z");
  app.add_option("--up", up, "camera up direction (with --eye and --target; default 0,0,1)")->type_name("X,Y,Z");
  app.add_option("--fov", fov, "vertical field of view, degrees (default: the run's)")->type_name("D");
  app.add_option("--size", size, "frame size in pixels (default: the run's)")->type_name("WxH")->check(frame_size());
  app.add_option("--msaa", msaa, "multisample count (0: none; default: the run's)")->type_name("N")
      ->check(whole_number(0, 16));
  app.add_option("--style", style, "clinical, paper or debug (default: the run's)")->type_name("S");
  app.add_flag("--depth", depth, "also frames/depth_NNNNNN.png (16-bit, mm x 10)");
  app.add_flag("--labels", labels, "also frames/labels_NNNNNN.png (legend in camera.json)");
  app.add_flag("--video", video, "also video.mp4 (H.264 through the ffmpeg program)");
  app.add_option("--frames", max_frames, "redraw at most N frames")->type_name("N")->check(whole_number(0, 100000000));
  app.add_option("--timeout", limit_s, "wall-clock limit in seconds (default 3600; 0: none)")->type_name("S")
      ->check(seconds_limit());
  app.add_option("--max-bytes", limit_bytes, "largest render_record.bin read (default 8G; K/M/G suffix)")
      ->type_name("BYTES")->transform(byte_count());
  app.add_flag("-q,--quiet", quiet, "no summary line");
  if (args.empty()) {
    std::fputs(o.help().c_str(), stderr);
    return 2;
  }
  if (!o.parse(args)) return 0;
  if (dirs.size() != 1) usage_fail("softcut render: give exactly one run folder (got ", dirs.size(), ")");
  if (limit_bytes == 0) limit_bytes = std::numeric_limits<std::uint64_t>::max();  // --max-bytes 0: no limit
  if (app.count("--eye") != app.count("--target"))
    usage_fail("softcut render: give --eye and --target together (a fixed camera), or neither (the run's camera)");
  if (app.count("--up") && !app.count("--eye")) usage_fail("softcut render: --up goes with --eye and --target");

  const fs::path run_dir = dirs[0];
  std::error_code ec;
  if (!fs::is_directory(run_dir, ec)) fail(run_dir.string(), ": not a folder (give the output folder of a run)");
  const std::string what = (run_dir / sim::kRenderRecordFile).string();
  std::string bytes;
  try {
    bytes = read_below(run_dir, sim::kRenderRecordFile, "render record", std::size_t(limit_bytes));
  } catch (const Error& e) {
    if (!fs::exists(fs::symlink_status(run_dir / sim::kRenderRecordFile, ec)))
      fail(what, ": missing: the run kept no render record (it rendered no frames, or it was too large: run it "
                 "again with --record)");
    throw;
  }
  sim::RenderRecordReader reader(bytes, what);
  sim::RecordMeta meta = sim::parse_record_meta(reader.meta(), what);

  // The command line's choices over the run's.
  sim::RenderSettings& rs = meta.render;
  if (app.count("--size")) rs.width = size.width, rs.height = size.height;
  if (app.count("--msaa")) rs.msaa_samples = msaa;
  if (app.count("--style")) {
    if (style == "clinical") rs.style = sim::RenderSettings::Style::clinical;
    else if (style == "paper") rs.style = sim::RenderSettings::Style::paper;
    else if (style == "debug") rs.style = sim::RenderSettings::Style::debug;
    else usage_fail("--style ", style, ": expected clinical, paper or debug");
    rs.show_forces = rs.show_loads = rs.style == sim::RenderSettings::Style::debug;
  }
  rs.depth = depth, rs.labels = labels, rs.video = video;
  const bool fixed_camera = app.count("--eye") > 0;
  const Eigen::Vector3d eye_v = fixed_camera ? parse_vec3(eye, "--eye") : Eigen::Vector3d::Zero();
  const Eigen::Vector3d target_v = fixed_camera ? parse_vec3(target, "--target") : Eigen::Vector3d::Zero();
  const Eigen::Vector3d up_v = app.count("--up") ? parse_vec3(up, "--up") : Eigen::Vector3d::UnitZ();
  double fov_deg = 0;
  if (app.count("--fov")) {
    std::size_t used = 0;
    try {
      fov_deg = std::stod(fov, &used);
    } catch (...) {
      used = 0;
    }
    if (used != fov.size() || !(fov_deg > 1 && fov_deg < 179)) usage_fail("--fov ", fov, ": expected degrees in (1, 179)");
  }

  // The frames go beside the record, never over the run's own outputs.
  const fs::path out = out_dir.empty() ? run_dir / "rendered" : fs::path(out_dir);
  fs::create_directories(out, ec);
  if (ec || !fs::is_directory(out))
    fail(out.string(), ": cannot create the output folder (", ec ? ec.message() : "not a folder", ")");
  if (fs::equivalent(out, run_dir, ec))
    usage_fail("softcut render: --out ", out.string(), " is the run's own folder; give another (default RUNDIR/rendered)");
  sim::clear_earlier_outputs(out);
  sim::remove_stale_video_folders(out);  // a killed render's (before this one's encoder starts)

  Watchdog dog(limit_s, std::clamp(limit_s / 10, 5.0, 60.0),
               cat("softcut render: the wall-clock limit of ", limit_s, " s (--timeout) passed and it did not stop"));
  OutputBudget budget(0);
  gl::EglContext context;
  render::FrameWriter writer(context, render::FrameWriter::Mode::worker, 2, &budget);
  if (rs.video)
    writer.attach_video(std::make_unique<render::VideoEncoder>(out / "video.mp4", rs.width, rs.height,
                                                               meta.fps / rs.every));
  sim::FrameOutputs frames_out(out, sim::FrameOutputOptions{rs.depth, rs.labels, meta.legend}, writer, &budget);
  render::SceneExtractor extractor;
  Timer wall;
  sim::RecordFrame f;
  Eigen::MatrixX3d positions;
  render::SceneContent content;
  int drawn = 0;
  while ((max_frames < 0 || drawn < max_frames) && reader.next(f)) {
    if (dog.expired().load()) throw TimeoutError(cat("softcut render: the wall-clock limit of ", limit_s, " s (--timeout) passed"));
    const sim::RecordTopology& topo = reader.topology(f.topology);
    sim::scene_inputs(topo, f, positions, content);
    render::CameraSettings camera = f.camera;
    if (fixed_camera) camera.auto_frame = false, camera.eye = eye_v, camera.target = target_v, camera.up = up_v;
    if (fov_deg > 0) camera.fov_y_deg = fov_deg;
    try {
      frames_out.submit(extractor.extract(topo.mesh, positions, content, sim::render_settings(rs, meta.palette, camera)),
                        f.frame, f.time);
    } catch (const Error& e) {
      fail(what, ": frame ", f.frame, ": ", e.what());
    }
    ++drawn;
  }
  frames_out.finish(rs.contact_sheet && drawn > 0);
  const double s = wall.seconds();
  if (!quiet)
    std::fprintf(stderr, "%s: %d frames redrawn in %.2f s (%.1f ms/frame) -> %s\n", meta.scenario.c_str(), drawn, s,
                 drawn ? 1e3 * s / drawn : 0.0, out.c_str());
  return 0;
}

}  // namespace softcut::app
