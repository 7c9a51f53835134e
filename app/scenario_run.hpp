#pragma once
// One scenario run end to end, on the application's side: the script
// (sim::ScenarioScript; a Lua file unless the caller opens another) gives
// the ScenarioSpec; the command line's overrides are applied; the output
// folder, the EGL context and the frame writer are made; compile; sim::run's
// frame loop calls the script's on_frame and checks; the outcome lists the
// expectations' verdicts. The CLI (softcut run / check / sweep) and the
// render bench call this; it needs no Lua headers.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim/run.hpp"
#include "sim/scenario_script.hpp"
#include "sim/scenario_spec.hpp"

namespace softcut {
class OutputBudget;
class Watchdog;
}  // namespace softcut

namespace softcut::app {

struct RunRequest {
  std::filesystem::path scenario;                 // the .lua file
  std::filesystem::path scenario_root;            // set: read `scenario` below it without following a link
                                                  // (softcut check: the folder the user named)
  std::filesystem::path out_dir;                  // empty: renders/<scenario name>/ under the working folder
  std::map<std::string, std::string> overrides;   // --set key=value (the scenario's params{})
  int max_frames = -1;                            // --frames N (>= 0)
  bool trusted = false;                           // --trust: no sandbox
  std::filesystem::path cache_dir;                // precompute cache folder (--no-cache: empty)
  bool render = true;                             // false: skip rendered frames (softcut check)
  std::optional<backend::Backend> backend;            // --backend: overrides s:solver{ backend }; none: the scenario's
  int render_every = 0;                           // --render-every N: render every N-th frame, also when the
                                                  // scenario renders none; 0: the scenario's choice
  int width = 0, height = 0;                      // --size WxH: overrides the render size; 0: the scenario's
  int msaa_samples = -1;                          // --msaa N: overrides the samples; -1: the scenario's
  bool depth = false, labels = false;             // --depth, --labels: also those images (rendering on)
  bool video = false;                             // --video: also video.mp4 (rendering on)
  std::optional<bool> record;                     // --record / --no-record: render_record.bin; none: the scenario's
  bool render_inline = false;                     // draw on the frame thread even without the GPU solver (bench)
  long long instruction_budget = 200'000'000;     // sandbox: Lua VM instructions per call (main chunk, each on_frame)
  std::size_t memory_budget = 512u << 20;         // sandbox: Lua heap, bytes
  double max_tets = 2'000'000;                    // sandbox: tetrahedra of the scenario's mesh (--max-tets)
  double timeout_s = 3600;                        // wall-clock limit of the whole run, s (--timeout; 0: none)
  std::uint64_t max_output = std::uint64_t(4) << 30;  // bytes the run may write, all files (--max-output; 0: none)
  std::function<void(int frame, int num_frames, double elapsed_s)> progress;
  const std::atomic<bool>* interrupt = nullptr;   // set by SIGINT/SIGTERM
  std::vector<std::string> command_line;          // for summary.json (the CLI's argv)
  bool warnings_as_errors = false;                // --warnings-as-errors: a run that warned fails (the commands)
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
  std::string mesh_fingerprint;  // of the rest mesh (reference_log.hpp), for reference headers
  std::vector<std::pair<std::string, std::string>> params;  // after --set, as the script saw them
  std::filesystem::path out_dir;
  double tolerance = 1e-6;  // reference comparison, relative to max |u_ref|
  int num_frames = 0;       // of the timeline
  sim::RunResult result;
  // Means per frame, ms: the simulation step, and per rendered frame the
  // frame loop's share of rendering and the drawing side (as in summary.json).
  double step_ms = 0, render_ms = 0, render_work_ms = 0;
  // The drawing side's parts per rendered frame, ms: the colour image (upload,
  // draw, read-back, PNG, write), the depth and label images, the video.
  double render_rgb_ms = 0, render_labels_ms = 0, render_video_ms = 0;
  int frames_rendered = 0;
  std::vector<ExpectationResult> expectations;
  std::vector<std::string> warnings;
};

// Opens the run's script. Made after the run's watchdog and output budget,
// which the script's sandbox is given (and which outlive it).
using OpenScript = std::function<std::unique_ptr<sim::ScenarioScript>(const RunRequest& req, OutputBudget* output,
                                                                      const Watchdog* watchdog)>;
// req.scenario as a sandboxed Lua scenario (lua/scenario_script.hpp).
std::unique_ptr<sim::ScenarioScript> open_lua_scenario(const RunRequest& req, OutputBudget* output,
                                                       const Watchdog* watchdog);

// Throws softcut::Error (with the scenario's file:line) for script errors,
// misuse and engine errors; after the frame loop started, the outputs are
// finished (summary marks the error) before the error propagates; a run past
// req.timeout_s throws TimeoutError.
RunOutcome run_scenario(const RunRequest& req, const OpenScript& open = open_lua_scenario);

// Only the script part: runs the scenario file and returns its spec (tests,
// `softcut check` listing). Same errors as run_scenario.
sim::ScenarioSpec load_scenario_spec(const RunRequest& req, const OpenScript& open = open_lua_scenario);

}  // namespace softcut::app
