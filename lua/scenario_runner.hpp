#pragma once
// Runs one Lua scenario end to end: sandboxed script -> ScenarioSpec ->
// compile -> frame loop with the script's on_frame and expectations ->
// displacements.csv + summary.json. The CLI (softcut run / check) calls this;
// it needs no Lua headers.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sim/run.hpp"
#include "sim/scenario_spec.hpp"

namespace softcut::lua {

struct RunRequest {
  std::filesystem::path scenario;                 // the .lua file
  std::filesystem::path out_dir;                  // empty: renders/<scenario name>/ under the working folder
  std::map<std::string, std::string> overrides;   // --set key=value (the scenario's params{})
  int max_frames = -1;                            // --frames N (>= 0)
  bool trusted = false;                           // --trust: no sandbox
  std::filesystem::path cache_dir;                // precompute cache folder (--no-cache: empty)
  bool render = true;                             // false: skip rendered frames (softcut check)
  std::optional<sim::Backend> backend;            // --backend: overrides s:solver{ backend }; none: the scenario's
  int render_every = 0;                           // --render-every N: render every N-th frame, also when the
                                                  // scenario renders none; 0: the scenario's choice
  int width = 0, height = 0;                      // --size WxH: overrides the render size; 0: the scenario's
  int msaa_samples = -1;                          // --msaa N: overrides the samples; -1: the scenario's
  bool render_inline = false;                     // draw on the frame thread even without the GPU solver (bench)
  long long instruction_budget = 200'000'000;     // sandbox: Lua VM instructions per call (main chunk, each on_frame)
  std::size_t memory_budget = 512u << 20;         // sandbox: Lua heap, bytes
  double max_tets = 2'000'000;                    // sandbox: tetrahedra of the scenario's mesh (--max-tets)
  double timeout_s = 3600;                        // wall-clock limit of the whole run, s (--timeout; 0: none)
  std::uint64_t max_output = std::uint64_t(4) << 30;  // bytes the run may write, all files (--max-output; 0: none)
  std::function<void(int frame, int num_frames, double elapsed_s)> progress;
  const std::atomic<bool>* interrupt = nullptr;   // set by SIGINT/SIGTERM
  std::vector<std::string> command_line;          // for summary.json (the CLI's argv)
};

struct ExpectationResult {
  std::string name;
  std::string where;    // "scenario.lua:40"
  bool reached = false; // false: the run ended before `at`
  bool ok = false;
  std::string message;  // what was measured, or the check's message
};

struct RunOutcome {
  std::string name;         // scenario name (renders/<name>)
  std::string description;
  std::filesystem::path out_dir;
  double tolerance = 1e-6;  // reference comparison, relative to max |u_ref|
  int num_frames = 0;       // of the timeline
  sim::RunResult result;
  // Means per frame, ms: the simulation step, and per rendered frame the
  // frame loop's share of rendering and the drawing side (as in summary.json).
  double step_ms = 0, render_ms = 0, render_work_ms = 0;
  int frames_rendered = 0;
  std::vector<ExpectationResult> expectations;
  std::vector<std::string> warnings;
};

// Throws softcut::Error (with the scenario's file:line) for script errors,
// misuse and engine errors; after the frame loop started, the outputs are
// finished (summary marks the error) before the error propagates.
RunOutcome run_scenario(const RunRequest& req);

// Only the script part: runs the scenario file and returns its spec (tests,
// `softcut check` listing). Same errors as run_scenario.
sim::ScenarioSpec load_scenario_spec(const RunRequest& req);

}  // namespace softcut::lua
