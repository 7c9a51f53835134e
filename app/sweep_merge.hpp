#pragma once
// `softcut sweep merge DIR`: gathers the summary.json of every run of the
// plan in DIR/sweep_plan.json into one table, DIR/sweep.csv and DIR/sweep.json
// (docs/sweeps.md). Timings are left out, so the table of a sweep depends
// only on its results: one local run and any sharding merge to the same bytes.
#include <filesystem>
#include <string>
#include <vector>

namespace softcut::app {

struct SweepMerge {
  int runs = 0, passed = 0, failed = 0;
  std::vector<std::string> missing;  // ids of runs without a summary.json
  std::string csv, json;             // the table, when nothing is missing
};

// Reads DIR's plan and summaries. Throws Error naming the file for a
// malformed plan or summary, or a summary from another sweep (its params
// differ from the plan's); a missing summary is listed, not thrown.
SweepMerge merge_sweep(const std::filesystem::path& dir);

}  // namespace softcut::app
