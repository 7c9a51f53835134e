// softcut bench render: what rendering costs a paper-size frame. Runs each
// scenario (default: the paper's two models, knee ligament and upper leg:
// whole frames with tools, both regions and logging) in one process:
// without frames, rendering every frame on the frame thread, on the worker
// thread (what `softcut run` does), on the worker with depth and label
// images, and on the worker with a video; then redraws the last run from its
// render record (`softcut render`) and compares its wall time with the run's.
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "app/commands.hpp"
#include "app/option_values.hpp"
#include "app/options.hpp"
#include "app/run_support.hpp"
#include "app/scenario_run.hpp"
#include "bench/bench.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/timer.hpp"
#include "render/video_encoder.hpp"

namespace softcut::bench {

int bench_render(const Args& args) {
  app::Options o("softcut bench render", "Runs each scenario (default: scenarios/knee_ligament.lua and "
                 "scenarios/upper_leg.lua, the paper's models; run from the repository root) without frames, "
                 "rendering every frame inline, on the worker thread, on the worker with depth and label images, "
                 "and on the worker with a video; compares the time per frame, the depth and label images' cost "
                 "with the colour frame's, and `softcut render`'s redraw with the run.");
  std::vector<std::string> scenarios;
  app::FrameSize size{640, 480};
  int samples = 4, frames = -1;
  o.app().add_option("scenario", scenarios, "scenario files")->type_name("SCENARIO.lua...");
  o.app().add_option("--size", size, "frame size (default 640x480)")->type_name("WxH")->check(app::frame_size());
  o.app().add_option("--msaa", samples, "MSAA samples (default 4)")->type_name("S")
      ->check(app::whole_number(0, 100000000));
  o.app().add_option("--frames", frames, "frames per run (default: the scenario's)")->type_name("N")
      ->check(app::whole_number(0, 100000000));
  std::string json_path;
  o.app().add_option("--json", json_path, "also write the results as JSON")->type_name("FILE");
  if (!o.parse(args)) return 0;
  const int width = size.width, height = size.height;
  if (scenarios.empty()) scenarios = {"scenarios/knee_ligament.lua", "scenarios/upper_leg.lua"};
  for (const auto& s : scenarios)
    if (!std::filesystem::is_regular_file(s))
      fail("bench render: ", s, " not found (run from the repository root or give scenario files)");
  const bool video = !render::find_ffmpeg().empty();

  const auto dir = std::filesystem::temp_directory_path() / "softcut-bench-render";
  std::printf("%dx%d, MSAA %d, every frame rendered; %u hardware threads%s\n\n", width, height, samples,
              std::thread::hardware_concurrency(), video ? "" : "; no ffmpeg: no video run");
  std::printf("| scenario | frames | loop | wall ms / frame | step ms / frame | frame thread render ms | "
              "drawing side ms | colour ms | depth + labels ms | video ms | frame thread render / step |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|\n");
  Json json = {{"benchmark", "render"}, {"width", width}, {"height", height}, {"msaa", samples},
               {"scenarios", Json::array()}};
  for (const auto& path : scenarios) {
    struct Loop {
      const char* name;
      bool render, inline_draw, aux, video;
      app::RunOutcome out;
      double total_s = 0;  // the whole run: script, compile (cached precompute), context, frame loop, outputs
    };
    std::vector<Loop> loops = {{"no frames", false, false, false, false, {}},
                               {"inline", true, true, false, false, {}},
                               {"worker", true, false, false, false, {}},
                               {"worker + depth + labels", true, false, true, false, {}}};
    if (video) loops.push_back({"worker + video", true, false, false, true, {}});
    for (Loop& l : loops) {
      app::RunRequest req;
      req.scenario = path;
      req.out_dir = dir / l.name;
      req.max_frames = frames;
      req.render = l.render;
      req.render_every = 1;
      req.render_inline = l.inline_draw;
      req.width = width, req.height = height, req.msaa_samples = samples;
      req.depth = req.labels = l.aux;
      req.video = l.video;
      if (l.render && !l.inline_draw && !l.aux && !l.video) req.record = true;  // the worker run is redrawn below
      Timer whole;
      l.out = app::run_scenario(req);
      l.total_s = whole.seconds();
    }
    Json rows = Json::array();
    for (const Loop& l : loops) {
      const app::RunOutcome& r = l.out;
      const int n = std::max(1, r.result.frames);
      std::printf("| %s | %d | %s | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.2f |\n", r.name.c_str(),
                  r.result.frames, l.name, 1e3 * r.result.wall_s / n, r.step_ms, r.render_ms, r.render_work_ms,
                  r.render_rgb_ms, r.render_labels_ms, r.render_video_ms, r.render_ms / std::max(r.step_ms, 1e-9));
      rows.push_back({{"loop", l.name}, {"frames", r.result.frames}, {"wall_ms_per_frame", field(1e3 * r.result.wall_s / n)},
                      {"step_ms", field(r.step_ms)}, {"frame_thread_render_ms", field(r.render_ms)},
                      {"drawing_side_ms", field(r.render_work_ms)}, {"rgb_ms", field(r.render_rgb_ms)},
                      {"depth_labels_ms", field(r.render_labels_ms)}, {"video_ms", field(r.render_video_ms)}});
    }
    const Loop& worker = loops[2];
    const Loop& aux = loops[3];
    // The redraw of the worker run from its record, at the same size and frame count.
    Timer t;
    const int rc = app::cmd_render({(dir / worker.name).string(), "--out", (dir / "redraw").string(), "-q"});
    const double redraw_s = t.seconds();
    if (rc != 0) fail("bench render: softcut render failed on ", (dir / worker.name).string());
    const double labels_ratio = aux.out.render_labels_ms / std::max(aux.out.render_rgb_ms, 1e-9);
    std::printf("| %s | | worker wall / no frames wall | %.2f | | | | | | | |\n", worker.out.name.c_str(),
                worker.out.result.wall_s / std::max(loops[0].out.result.wall_s, 1e-9));
    std::printf("| %s | | depth + labels / colour frame | %.2f | | | | | | | |\n", worker.out.name.c_str(), labels_ratio);
    std::printf("| %s | | softcut render wall / run's frame loop wall (%.2f s / %.2f s) | %.2f | | | | | | | |\n",
                worker.out.name.c_str(), redraw_s, worker.out.result.wall_s,
                redraw_s / std::max(worker.out.result.wall_s, 1e-9));
    std::printf("| %s | | softcut render wall / whole run wall (%.2f s / %.2f s) | %.2f | | | | | | | |\n",
                worker.out.name.c_str(), redraw_s, worker.total_s, redraw_s / std::max(worker.total_s, 1e-9));
    Json entry = {{"scenario", worker.out.name}, {"loops", rows},
                  {"worker_wall_over_no_frames", field(worker.out.result.wall_s / std::max(loops[0].out.result.wall_s, 1e-9))},
                  {"depth_labels_over_rgb", field(labels_ratio)},
                  {"redraw_wall_s", field(redraw_s)}, {"run_wall_s", field(worker.out.result.wall_s)},
                  {"redraw_over_run", field(redraw_s / std::max(worker.out.result.wall_s, 1e-9))},
                  {"run_total_s", field(worker.total_s)},
                  {"redraw_over_run_total", field(redraw_s / std::max(worker.total_s, 1e-9))}};
    if (video) {
      const Loop& v = loops[4];
      entry["video_frame_thread_render_ms"] = field(v.out.render_ms);
      entry["video_writer_ms"] = field(v.out.render_video_ms);
    }
    json["scenarios"].push_back(entry);
  }
  std::filesystem::remove_all(dir);
  std::printf("\nframe thread render: scene extraction + hand-over (+ waiting when the writer is behind);\n"
              "inline it also draws, encodes and writes. drawing side: upload, draw, readback, PNG, write\n"
              "(colour), plus the depth and label pass and PNGs, plus handing the frame to ffmpeg (video).\n"
              "softcut render: redrawing the worker run from its record, against the run's frame loop and\n"
              "against the whole run (script, compile with the cached precompute, context, frames, outputs).\n");
  if (!json_path.empty()) write_file_atomic(json_path, json_text(json));
  return 0;
}

}  // namespace softcut::bench
