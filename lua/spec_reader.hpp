#pragma once
// The engine's copy of a scenario: the Scenario table the script built,
// read into a sim::ScenarioSpec with raw access only (no script code runs;
// a metamethod cannot lie about a length), inside a protected call charged
// to the script's instruction budget.
#include <filesystem>

#include "sim/scenario_spec.hpp"

struct lua_State;

namespace softcut::lua {

// Reads the Scenario table at stack index `s`; `source` (the .lua file)
// names the spec's source and the messages. Throws softcut::Error with the
// scenario's file (and line, where the script recorded one).
sim::ScenarioSpec read_spec(lua_State* L, int s, const std::filesystem::path& source);

}  // namespace softcut::lua
