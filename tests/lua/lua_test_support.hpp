#pragma once
// Helpers for the Lua layer tests: run snippets and scenario files through
// the real runtime and return the error message ("" when none).
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "runtime.hpp"
#include "app/scenario_run.hpp"
#include "test_support.hpp"

namespace softcut::test {

// Runs `code` as a chunk named "@<dir>/snippet.lua" (so messages carry that
// file:line); returns the error message or "".
inline std::string lua_error(const std::string& code, lua::SandboxOptions opt = {}) {
  try {
    lua::Runtime rt(opt);
    rt.run_string(code, "@snippet.lua", 0);
    return "";
  } catch (const Error& e) {
    return e.what();
  }
}

// Writes `text` to <scratch(name)>/<file> and returns its path.
inline std::filesystem::path write_scenario(const std::string& name, const std::string& text,
                                            const std::string& file = "scenario.lua") {
  const auto dir = scratch_dir(name);
  std::ofstream(dir / file) << text;
  return dir / file;
}

// A small valid scenario head: a 4x2x2 box of 0.1 x 0.04 x 0.04 m, liver,
// fixed at x = 0; `s` and `m` are defined, `tip` selects the x = 0.1 face.
inline const char* kBoxHead = R"(
local s = softcut.scenario{ duration = 0.5, fps = 10 }
local m = s:mesh{ generate = "box", options = { min = {0, 0, 0}, max = {0.1, 0.04, 0.04}, nx = 4, ny = 2, nz = 2 } }
s:material{ tissue = "liver" }
s:fix{ nodes = softcut.select.box{ min = {0, 0, 0}, max = {0, 0.04, 0.04} } }
local tip = softcut.select.box{ min = {0.1, 0, 0}, max = {0.1, 0.04, 0.04} }
)";

// Runs a scenario file; returns the error message or "" (outcome in *out).
inline std::string scenario_error(const std::filesystem::path& file, app::RunOutcome* out = nullptr,
                                  app::RunRequest req = {}) {
  req.scenario = file;
  if (req.out_dir.empty()) req.out_dir = file.parent_path() / "out";
  if (!req.backend) req.backend = softcut::backend::Backend::cpu;  // no EGL context per test run (auto would probe for a GPU)
  try {
    app::RunOutcome o = app::run_scenario(req);
    if (out) *out = o;
    return "";
  } catch (const Error& e) {
    return e.what();
  }
}


}  // namespace softcut::test
