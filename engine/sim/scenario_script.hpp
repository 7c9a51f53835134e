#pragma once
// What a run needs of the script that describes it. lua/ implements it for
// Lua scenario files (lua/scenario_script.hpp); the application's run
// (app/scenario_run.hpp) drives it, so a run and its verdicts can be made
// and tested without Lua.
#include <filesystem>
#include <string>
#include <utility>

#include "sim/scenario_spec.hpp"

namespace softcut::sim {

struct Model;
struct State;

class ScenarioScript {
 public:
  virtual ~ScenarioScript() = default;

  // The scenario as plain data, read from what the script built (no script
  // code runs). Throws softcut::Error naming the script's file and line.
  virtual ScenarioSpec spec() = 0;
  // From now on the script may write files only below `dir` (the run's
  // output folder, made and resolved by the application).
  virtual void confine_writes(const std::filesystem::path& dir) = 0;
  // Once, after compile and before the first frame.
  virtual void start() = 0;
  // After each recorded frame: may move tools, change loads and request a
  // stop through the State; false ends the run after this frame.
  virtual bool on_frame(const Model& m, State& s) = 0;
  // The check function of expectation `index` (into spec().expectations),
  // when it is due: (ok, message).
  virtual std::pair<bool, std::string> check(int index, const Model& m, State& s) = 0;
};

}  // namespace softcut::sim
