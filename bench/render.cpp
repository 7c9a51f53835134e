// softcut bench render: what rendering costs a paper-size frame. Runs the
// scenarios of the paper's two models (knee ligament, upper leg: whole frames
// with tools, both regions and logging, the sizes of Wu & Heng 2005) three
// times in one process: without frames, rendering every frame on the frame
// thread, and rendering every frame on the worker thread (what `softcut run`
// does), and compares the frame loop's time.
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench.hpp"
#include "app/option_values.hpp"
#include "app/options.hpp"
#include "app/run_support.hpp"
#include "core/error.hpp"
#include "app/scenario_run.hpp"

namespace softcut::bench {

int bench_render(const Args& args) {
  app::Options o("softcut bench render", "Runs each scenario (default: scenarios/knee_ligament.lua and "
                 "scenarios/upper_leg.lua, the paper's models; run from the repository root) without frames, "
                 "rendering every frame inline and rendering every frame on the worker thread, and compares the "
                 "time per frame.");
  std::vector<std::string> scenarios;
  app::FrameSize size{640, 480};
  int samples = 4, frames = -1;
  o.app().add_option("scenario", scenarios, "scenario files")->type_name("SCENARIO.lua...");
  o.app().add_option("--size", size, "frame size (default 640x480)")->type_name("WxH")->check(app::frame_size());
  o.app().add_option("--msaa", samples, "MSAA samples (default 4)")->type_name("S")
      ->check(app::whole_number(0, 100000000));
  o.app().add_option("--frames", frames, "frames per run (default: the scenario's)")->type_name("N")
      ->check(app::whole_number(0, 100000000));
  if (!o.parse(args)) return 0;
  const int width = size.width, height = size.height;
  if (scenarios.empty()) scenarios = {"scenarios/knee_ligament.lua", "scenarios/upper_leg.lua"};
  for (const auto& s : scenarios)
    if (!std::filesystem::is_regular_file(s))
      fail("bench render: ", s, " not found (run from the repository root or give scenario files)");

  const auto dir = std::filesystem::temp_directory_path() / "softcut-bench-render";
  std::printf("%dx%d, MSAA %d, every frame rendered; %u hardware threads\n\n", width, height, samples,
              std::thread::hardware_concurrency());
  std::printf("| scenario | frames | loop | wall ms / frame | step ms / frame | frame thread render ms | "
              "drawing side ms | frame thread render / step |\n|---|---|---|---|---|---|---|---|\n");
  for (const auto& path : scenarios) {
    struct Loop {
      const char* name;
      bool render, inline_draw;
      app::RunOutcome out;
    };
    Loop loops[] = {{"no frames", false, false, {}}, {"inline", true, true, {}}, {"worker", true, false, {}}};
    for (Loop& l : loops) {
      app::RunRequest req;
      req.scenario = path;
      req.out_dir = dir / l.name;
      req.max_frames = frames;
      req.render = l.render;
      req.render_every = 1;
      req.render_inline = l.inline_draw;
      req.width = width, req.height = height, req.msaa_samples = samples;
      l.out = app::run_scenario(req);
    }
    for (const Loop& l : loops) {
      const app::RunOutcome& o = l.out;
      const int n = std::max(1, o.result.frames);
      std::printf("| %s | %d | %s | %.3f | %.3f | %.3f | %.3f | %.2f |\n", o.name.c_str(), o.result.frames, l.name,
                  1e3 * o.result.wall_s / n, o.step_ms, o.render_ms, o.render_work_ms,
                  o.render_ms / std::max(o.step_ms, 1e-9));
    }
    std::printf("| %s | | worker wall / no frames wall | %.2f | | | | |\n", loops[0].out.name.c_str(),
                loops[2].out.result.wall_s / std::max(loops[0].out.result.wall_s, 1e-9));
  }
  std::filesystem::remove_all(dir);
  std::printf("\nframe thread render: scene extraction + hand-over (+ waiting when the writer is behind);\n"
              "inline it also draws, encodes and writes. drawing side: upload, draw, readback, PNG, write.\n");
  return 0;
}

}  // namespace softcut::bench
