#pragma once
// A run that did nothing says so (issue #40): at the end of a run, a tool
// that never touched the tissue (with its closest approach), a scalpel that
// touched but never cut (with its highest pressure), a tool whose window
// never opened. Coded warnings (core/warning.hpp) in State::warnings:
// tool_never_active, tool_never_touched, scalpel_never_cut.
#include <string>
#include <vector>

#include "sim/model.hpp"

namespace softcut::sim {

// The warnings for the tools of `s`; `complete`: the run reached its last
// frame or the script ended it (a run cut short by --frames, Ctrl-C, the
// deadline or an error did not give its tools their chance: none).
std::vector<std::string> idle_tool_warnings(const Model& m, const State& s, bool complete);

}  // namespace softcut::sim
