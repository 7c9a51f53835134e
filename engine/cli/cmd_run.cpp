// softcut run SCENARIO.lua [--out DIR] [--set key=value ...] [--frames N] [--size WxH] [--msaa N] ...
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <tuple>

#include "cli/commands.hpp"
#include "cli/run_support.hpp"
#include "core/error.hpp"
#include "hybrid/precompute_cache.hpp"
#include "app/scenario_run.hpp"

namespace softcut::cli {

namespace {

const char* kRunUsage =
    "usage: softcut run SCENARIO.lua [--out DIR] [--set key=value ...] [--frames N] [--backend B]\n"
    "                   [--render-every N] [--size WxH] [--msaa N] [--max-tets N] [--timeout S]\n"
    "                   [--max-output BYTES] [--quiet] [--trust] [--no-render] [--no-cache]\n"
    "\n"
    "Runs a Lua scenario headless and writes DIR/displacements.csv and DIR/summary.json\n"
    "(default DIR: renders/<scenario name>/).\n"
    "  --out DIR        output folder\n"
    "  --set key=value  override a parameter the scenario declares with softcut.params{...}\n"
    "  --frames N       stop after N frames\n"
    "  --backend B      operational solver: auto, cpu, gpu, direct or monolithic (overrides the scenario)\n"
    "  --render-every N render every N-th frame (also when the scenario renders none)\n"
    "  --size WxH       rendered frame size in pixels (overrides the scenario's, e.g. 640x480)\n"
    "  --msaa N         multisample count of rendered frames (0: none; overrides the scenario's)\n"
    "  --quiet          no progress output\n"
    "  --max-tets N     sandbox: largest mesh the scenario may load or generate (default 2000000 tets)\n"
    "  --timeout S      wall-clock limit of the run in seconds (default 3600; 0: none); the run then\n"
    "                   stops, writes its outputs and exits 124 (exit_reason \"timeout\")\n"
    "  --max-output B   bytes the run may write, all files together (default 4G; 0: none; K/M/G suffix)\n"
    "  --trust          no sandbox: full Lua standard library, no instruction, memory or mesh budget\n"
    "  --no-render      write no frames (also when no OpenGL context can be made)\n"
    "  --no-cache       redo the hybrid precompute instead of loading it from the cache\n"
    "                   ($SOFTCUT_CACHE_DIR, else $XDG_CACHE_HOME/softcut or ~/.cache/softcut)\n"
    "Ctrl-C (SIGINT) or SIGTERM stops the script at once (also inside pcall), finishes the current\n"
    "frame, writes the outputs and marks the summary interrupted; a second one ends the process\n"
    "at once, without outputs.\n"
    "Exit status: 0 done, 1 an error or a failed expectation (outputs still written; one the\n"
    "run did not reach counts only if the run completed), 2 usage, 124 wall-clock limit\n"
    "(--timeout), 130 interrupted.\n";

}  // namespace

int cmd_run(const Args& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::fputs(kRunUsage, args.empty() ? stderr : stdout);
    return args.empty() ? 2 : 0;
  }
  app::RunRequest req;
  req.cache_dir = hybrid::default_cache_dir();
  req.command_line = {"softcut", "run"};
  req.command_line.insert(req.command_line.end(), args.begin(), args.end());
  bool quiet = false;
  std::vector<std::string> files;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&](const char* opt) -> const std::string& {
      if (i + 1 >= args.size()) usage_fail("softcut run: ", opt, " needs a value (see softcut run --help)");
      return args[++i];
    };
    if (a == "--out") req.out_dir = value("--out");
    else if (a == "--set") add_override(req.overrides, value("--set"));
    else if (a.rfind("--set=", 0) == 0) add_override(req.overrides, a.substr(6));
    else if (a == "--frames") req.max_frames = parse_count(value("--frames"), "--frames");
    else if (a == "--backend") req.backend = parse_backend(value("--backend"));
    else if (a == "--render-every") req.render_every = std::max(1, parse_count(value("--render-every"), "--render-every"));
    else if (a == "--size") std::tie(req.width, req.height) = parse_size(value("--size"), "--size");
    else if (a == "--msaa") req.msaa_samples = parse_count(value("--msaa"), "--msaa");
    else if (a == "--quiet" || a == "-q") quiet = true;
    else if (a == "--max-tets") req.max_tets = parse_count(value("--max-tets"), "--max-tets");
    else if (a == "--timeout") req.timeout_s = parse_seconds(value("--timeout"), "--timeout");
    else if (a == "--max-output") req.max_output = parse_bytes(value("--max-output"), "--max-output");
    else if (a == "--trust") req.trusted = true;
    else if (a == "--no-render") req.render = false;
    else if (a == "--no-cache") req.cache_dir.clear();
    else if (a.rfind("-", 0) == 0) usage_fail("softcut run: unknown option '", a, "' (see softcut run --help)");
    else files.push_back(a);
  }
  if (files.size() != 1) usage_fail("softcut run: give exactly one scenario file (got ", files.size(), ")");
  req.scenario = files[0];

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
  return failed ? 1 : 0;  // outputs are written either way; CI sees the failed expectation
}

}  // namespace softcut::cli
