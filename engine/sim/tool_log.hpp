#pragma once
// What each tool did, frame by frame (tools.csv, docs/outputs.md) and over
// the run (summary.json "tools"): whether it was engaged, on how many nodes,
// and the force it applied to the tissue.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/json_text.hpp"
#include "sim/model.hpp"

namespace softcut::sim {

// The force tool `k` applies to the tissue this frame, N: the sum of its
// nodal forces that reach the elastic solve. A share on a fixed node goes
// straight into the support and a piece cut free takes none, so neither is
// counted; so it equals the sum of the reactions K u - f_other at its nodes.
Eigen::Vector3d applied_tool_force(const Model& m, const State& s, int k);

// "frame,time,tool,kind,engaged,nodes,fx,fy,fz,pressure,cut\n"
extern const char* const kToolLogHeader;
// One row per tool of s.tool_specs for the state's frame, in spec order.
std::string tool_log_rows(const Model& m, const State& s);

// Per tool over the frames recorded: engaged frames, the largest and the
// mean (over engaged frames) magnitude of the applied force; for a scalpel
// the largest contact pressure and the frames it cut.
struct ToolRunStats {
  std::string name, kind;
  int frames_engaged = 0, frames_cut = 0;
  double peak_force = 0, force_sum = 0, peak_pressure = 0;  // N, N, Pa
};

class ToolStatistics {
 public:
  void add(const Model& m, const State& s);
  Json json() const;  // summary.json "tools"
  const std::vector<ToolRunStats>& tools() const { return tools_; }

 private:
  std::vector<ToolRunStats> tools_;
};

}  // namespace softcut::sim
