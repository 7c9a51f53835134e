#pragma once
// A Lua scenario file as a run's script (sim::ScenarioScript): its main chunk
// runs in the sandbox, its tables become the ScenarioSpec, and its on_frame
// and check functions are called through the interface. The application's
// run (app/scenario_run.hpp) drives it; callers need no Lua headers.
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "runtime.hpp"
#include "sim/scenario_script.hpp"

namespace softcut {
class Watchdog;
}

namespace softcut::lua {

struct ScriptRequest {
  std::filesystem::path scenario;                // the .lua file
  // Set: `scenario` lies below this folder and is read through the checked
  // open (no link at or below the folder; a regular file of at most 64 MiB),
  // as `softcut check` reads the scenarios of a package.
  std::filesystem::path scenario_root;
  std::map<std::string, std::string> overrides;  // --set key=value (the scenario's params{})
  // Trust, budgets, interrupt and output budget. Its folders and deadline
  // are set here: read_dir is the scenario's folder, write_dir none until
  // ScenarioScript::confine_writes, the deadline the watchdog's.
  SandboxOptions sandbox;
  const Watchdog* watchdog = nullptr;            // the run's wall-clock limit: a script past it stops
};

// Runs the scenario file's main chunk (sandboxed unless trusted) and returns
// it as the run's script. Throws softcut::Error with the file:line for
// script errors, a missing file, a script that made no scenario, or --set
// on a scenario without params{}.
std::unique_ptr<sim::ScenarioScript> open_scenario(const ScriptRequest& req);

}  // namespace softcut::lua
