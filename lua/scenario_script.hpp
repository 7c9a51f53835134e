#pragma once
// A Lua scenario file as a run's script (sim::ScenarioScript): its main chunk
// runs in the sandbox, its tables become the ScenarioSpec, and its on_frame
// and check functions are called through the interface. The application's
// run (app/scenario_run.hpp) drives it; callers need no Lua headers.
#include <atomic>
#include <cstddef>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "sim/scenario_script.hpp"

namespace softcut {
class OutputBudget;
class Watchdog;
}  // namespace softcut

namespace softcut::lua {

struct ScriptRequest {
  std::filesystem::path scenario;                // the .lua file
  std::map<std::string, std::string> overrides;  // --set key=value (the scenario's params{})
  bool trusted = false;                          // --trust: no sandbox
  long long instruction_budget = 200'000'000;    // sandbox: Lua VM instructions per call (main chunk, each on_frame)
  std::size_t memory_budget = 512u << 20;        // sandbox: Lua heap, bytes
  double max_tets = 2'000'000;                   // sandbox: tetrahedra of the scenario's mesh (--max-tets)
  const std::atomic<bool>* interrupt = nullptr;  // set by SIGINT/SIGTERM: a running script stops
  OutputBudget* output = nullptr;                // what the script writes is counted here (--max-output)
  const Watchdog* watchdog = nullptr;            // the run's wall-clock limit: a script past it stops
};

// Runs the scenario file's main chunk (sandboxed unless trusted) and returns
// it as the run's script. Throws softcut::Error with the file:line for
// script errors, a missing file, a script that made no scenario, or --set
// on a scenario without params{}.
std::unique_ptr<sim::ScenarioScript> open_scenario(const ScriptRequest& req);

}  // namespace softcut::lua
