// softcut run SCENARIO.lua [--out DIR] [--set key=value ...] [--frames N] [--size WxH] [--msaa N] ...
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>

#include "app/commands.hpp"
#include "app/options.hpp"
#include "app/run_options.hpp"
#include "app/run_support.hpp"
#include "app/scenario_run.hpp"
#include "core/error.hpp"

namespace softcut::app {

namespace {

const char* kRunAbout =
    "Runs a Lua scenario headless and writes DIR/displacements.csv, DIR/tools.csv and DIR/summary.json\n"
    "(default DIR: renders/<scenario name>/), and its frames when it renders (with camera.json and\n"
    "render_record.bin, which softcut render redraws the frames from).";

const char* kRunFooter =
    "Ctrl-C (SIGINT) or SIGTERM stops the script at once (also inside pcall), finishes the current\n"
    "frame, writes the outputs and marks the summary interrupted (before the frame loop, e.g. in the\n"
    "precompute, it ends at once without outputs); a second one ends the process at once, without outputs.\n"
    "Exit status: 0 done, 1 an error or a failed expectation (outputs still written; one the\n"
    "run did not reach counts only if the run completed), 2 usage, 124 wall-clock limit\n"
    "(--timeout), 130 interrupted.";

}  // namespace

int cmd_run(const Args& args) {
  Options o("softcut run", kRunAbout, kRunFooter);
  CLI::App& app = o.app();
  std::vector<std::string> files;
  std::string out_dir;
  bool quiet = false, depth = false, labels = false, video = false, record = false, no_record = false;
  app.add_option("scenario", files, "the scenario file (SCENARIO.lua)")->type_name("SCENARIO.lua");
  app.add_option("--out", out_dir, "output folder")->type_name("DIR");
  o.needs("--out", "a folder");
  app.add_flag("--depth", depth, "also frames/depth_NNNNNN.png (16-bit, mm x 10 along the view axis) and camera.json; "
               "turns rendering on");
  app.add_flag("--labels", labels, "also frames/labels_NNNNNN.png (an id per pixel: each material, the cut surface, "
               "each tool; legend in camera.json); turns rendering on");
  app.add_flag("--video", video, "also video.mp4 (H.264 through the ffmpeg program: sudo apt-get install ffmpeg); "
               "turns rendering on");
  app.add_flag("--record", record, "write render_record.bin for softcut render, however large");
  app.add_flag("--no-record", no_record, "write no render_record.bin (default: when it stays under 256 MiB)");
  app.add_flag("-q,--quiet", quiet, "no progress output");
  RunOptions run(o, RunOptions::all);
  if (args.empty()) {
    std::fputs(o.help().c_str(), stderr);
    return 2;
  }
  if (!o.parse(args)) return 0;
  if (files.size() != 1) usage_fail("softcut run: give exactly one scenario file (got ", files.size(), ")");

  app::RunRequest req;
  run.apply(req);
  req.scenario = files[0];
  req.command_line = {"softcut", "run"};
  req.command_line.insert(req.command_line.end(), args.begin(), args.end());
  req.out_dir = out_dir;
  req.depth = depth, req.labels = labels, req.video = video;
  if (record && no_record) usage_fail("softcut run: give --record or --no-record, not both");
  if (record || no_record) req.record = record;

  Progress progress(quiet ? Progress::Mode::quiet : ::isatty(STDERR_FILENO) ? Progress::Mode::bar : Progress::Mode::lines);
  req.progress = [&](int frame, int n, double elapsed) { progress.update(frame, n, elapsed); };
  const SignalGuard signals;
  req.interrupt = &SignalGuard::flag();

  const app::RunOutcome out = app::run_scenario(req);
  progress.done();
  int failed = 0;
  for (const auto& w : out.warnings)
    if (!quiet) std::fprintf(stderr, "warning: %s\n", w.c_str());
  // An expectation the run never reached fails only when the run was meant to
  // reach it: not after --frames, Ctrl-C or a script's stop.
  const bool cut_short = out.result.reason != sim::ExitReason::completed;
  int skipped = 0;
  for (const auto& e : out.expectations) {
    if (e.ok) continue;
    if (!e.reached && cut_short) {
      ++skipped;
      continue;
    }
    ++failed;
    std::fprintf(stderr, "%s: expect '%s' failed: %s\n", e.where.c_str(), e.name.c_str(), e.message.c_str());
  }
  if (!quiet) {
    std::fprintf(stderr, "%s: %d frames, %s in %.2f s -> %s\n", out.name.c_str(), out.result.frames,
                 sim::to_string(out.result.reason), out.result.wall_s, out.out_dir.c_str());
    if (!out.expectations.empty())
      std::fprintf(stderr, "expectations: %d passed, %d failed, %d not reached (%s)\n",
                   int(out.expectations.size()) - failed - skipped, failed, skipped,
                   sim::to_string(out.result.reason));
  }
  if (out.result.reason == sim::ExitReason::interrupted) return 130;
  if (out.result.reason == sim::ExitReason::timeout) {
    std::fprintf(stderr, "softcut: error: %s: %s\n", out.name.c_str(), out.result.message.empty()
                 ? "the wall-clock limit (--timeout) was reached" : out.result.message.c_str());
    return 124;
  }
  if (req.warnings_as_errors && !out.warnings.empty()) {
    std::fprintf(stderr, "softcut: error: %s: %s\n", out.name.c_str(), warned_message(out.warnings).c_str());
    return 1;
  }
  return failed ? 1 : 0;  // outputs are written either way; CI sees the failed expectation
}

}  // namespace softcut::app
