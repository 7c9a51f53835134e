#pragma once
// summary.json (schema softcut-summary/1, docs/summary-schema.md): what a run
// did, how long each stage took, what it wrote and what it found.
#include <string>

#include "sim/model.hpp"
#include "sim/run.hpp"

namespace softcut::sim {

class Recorder;

// summary.json text; `rec` adds the outputs' statistics (rendering) when given.
std::string summary_json(const Model& m, const State& s, const RunResult& r, const Recorder* rec = nullptr);

}  // namespace softcut::sim
