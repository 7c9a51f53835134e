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
#include <tuple>
#include <vector>

#include "bench/bench.hpp"
#include "cli/run_support.hpp"
#include "core/error.hpp"
#include "app/scenario_run.hpp"

namespace softcut::bench {

int bench_render(const Args& args) {
  int width = 640, height = 480, samples = 4, frames = -1;
  std::vector<std::string> scenarios;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) usage_fail("bench render: ", a, " needs a value");
      return args[++i];
    };
    if (a == "--help" || a == "-h") {
      std::puts("usage: softcut bench render [--size WxH] [--msaa S] [--frames N] [SCENARIO.lua ...]\n"
                "  runs each scenario (default: scenarios/knee_ligament.lua and scenarios/upper_leg.lua,\n"
                "  the paper's models; run from the repository root) without frames, rendering every\n"
                "  frame inline and rendering every frame on the worker thread, at W x H (640x480)\n"
                "  with S MSAA samples (4), and compares the time per frame");
      return 0;
    } else if (a == "--size") {
      std::tie(width, height) = cli::parse_size(value(), "--size");
    } else if (a == "--msaa") {
      samples = cli::parse_count(value(), "--msaa");
    } else if (a == "--frames") {
      frames = cli::parse_count(value(), "--frames");
    } else if (a.rfind("-", 0) == 0) {
      usage_fail("bench render: unknown option '", a, "' (see softcut bench render --help)");
    } else {
      scenarios.push_back(a);
    }
  }
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
