#pragma once
// Expectations (Scenario:expect, docs/lua-api.md): checks at a time that
// `softcut check` and `softcut run` report and summary.json records. The run
// loop (sim/run.hpp) owns them: after each recorded frame it checks the due
// ones in declaration order, bounds here, check functions through
// RunHooks::check (the scenario layer's code), before the on_frame hook.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sim/selector.hpp"

namespace softcut::sim {

struct Model;
struct State;

// Most expectations one scenario may declare, longest name (bytes), and the
// most of a check function's message kept (bytes; longer ones are cut):
// what a run holds, prints and writes for them stays bounded (summary.json,
// softcut check's reports, sweep merge's table).
constexpr std::size_t kMaxExpectations = 10000;
constexpr std::size_t kMaxExpectationName = 1000;
constexpr std::size_t kMaxExpectationMessage = 1000;

struct ExpectationSpec {
  enum class Measure { mean, max };  // of the mean displacement vector; or over the nodes (largest |value|, signed)
  enum class Component { magnitude, x, y, z };
  std::string name;
  std::string where;  // "scenario.lua:40" (prefixes messages), may be empty
  double at = 0.0;    // s: checked at the first frame with time >= at - dt / 2
  // Bounds (m) on the displacement of `nodes` when `bounds`; else a check
  // function of the scenario layer, asked through RunHooks::check.
  bool bounds = false;
  NodeSelector nodes;
  Measure measure = Measure::mean;
  Component component = Component::magnitude;
  std::optional<double> min, max;  // at least one when `bounds`
};

// One expectation's outcome, in the run's State (spec order).
struct ExpectationOutcome {
  bool reached = false;  // false: the run ended before `at`
  bool ok = false;
  double time = 0.0;            // s, of the frame it was checked at (when reached)
  std::optional<double> value;  // m, the measured value (bounds only)
  std::string message;          // what was measured, the check's message, or why it was not reached
};

// A check function's verdict: (ok, message); the message may be empty.
using ExpectationCheck = std::function<std::pair<bool, std::string>(int index, const Model&, State&)>;

// Checks the expectations due at s.time that were not checked yet.
void check_due_expectations(const Model& m, State& s, const ExpectationCheck& check);

// Gives every expectation never reached its "not reached" message.
void mark_unreached_expectations(const Model& m, State& s);

const char* to_string(ExpectationSpec::Measure v);
const char* to_string(ExpectationSpec::Component v);

// "mean"/"max" and "magnitude"/"x"/"y"/"z": throw naming the accepted
// values with a did-you-mean.
ExpectationSpec::Measure parse_measure(std::string_view text);
ExpectationSpec::Component parse_component(std::string_view text);

}  // namespace softcut::sim
