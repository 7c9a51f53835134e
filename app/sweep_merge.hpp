#pragma once
// `softcut sweep merge DIR`: gathers the summary.json of every run of the
// plan in DIR/sweep_plan.json into one table, DIR/sweep.csv and DIR/sweep.json
// (docs/sweeps.md). Timings are left out, so the table of a sweep depends
// only on its results: one local run and any sharding merge to the same bytes.
//
// DIR may come from someone else: the plan and every summary are read
// through the checked open (a linked run_NNNN folder or summary is refused,
// never followed), each file and the table are bounded before they are
// built, and a summary is read field by field (a missing or mistyped field
// is an error naming the file and the field).
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace softcut::app {

// Largest summary.json read, bytes; most expectations one summary may list;
// most expectation columns; most cells (runs x expectation columns) of the table.
constexpr std::size_t kMaxSummaryBytes = std::size_t(64) << 20;
constexpr std::size_t kMaxSummaryExpectations = 10000;
constexpr std::size_t kMaxExpectationColumns = 10000;
constexpr std::size_t kMaxMergeCells = 10000000;
// Longest expectation name kept (longer: an error), and message kept (longer: cut).
constexpr std::size_t kMaxExpectationName = 1000;
constexpr std::size_t kMaxMergedMessage = 1000;
// Most tools a summary may list (a scenario has a handful); most metrics
// (Frame:record; softcut records at most 256).
constexpr std::size_t kMaxSummaryTools = 1000;
constexpr std::size_t kMaxSummaryMetrics = 1000;

// What merge reads of a run's summary.json.
struct RunSummary {
  std::vector<std::string> command_line;
  std::string exit_reason, message;
  nlohmann::json frames, last_time_s;         // numbers; last_time_s may be null
  nlohmann::json cut_events = 0, detached_pieces = 0;
  struct Expectation {
    std::string name;
    nlohmann::json value;  // a number, or null (a check function's: its verdict is the cell)
    bool pass = false, reached = false;
    std::string message;
  };
  std::vector<Expectation> expectations;
  // Per tool (summary.json "tools"; sweep.csv's tool.<name>.* columns).
  struct Tool {
    std::string name;
    nlohmann::json peak_force_n, mean_force_n, frames_engaged;  // numbers (forces may be null)
    nlohmann::json entry;  // the three with the name, for sweep.json
  };
  std::vector<Tool> tools;
  // Per recorded metric (summary.json "metrics"; sweep.csv's metric.<name> columns: the last value).
  struct Metric {
    std::string name;
    nlohmann::json value;  // a number
    nlohmann::json entry;  // name, value, min, max, mean, samples, for sweep.json
  };
  std::vector<Metric> metrics;
};

// Reads one summary's text (`file` names it in messages). Throws
// softcut::Error naming the file and the field: "run_0003/summary.json:
// 'run.exit_reason' is missing (not a summary softcut wrote; rerun the run)".
RunSummary parse_run_summary(const std::string& text, const std::string& file);

struct SweepMerge {
  int runs = 0, passed = 0, failed = 0;
  std::vector<std::string> missing;  // ids of runs without a summary.json
  std::string csv, json;             // the table, when nothing is missing
};

// Reads DIR's plan and summaries. Throws Error naming the file for a
// malformed plan or summary, a linked run folder or summary, a table past
// the bounds above, or a summary from another sweep (its params differ from
// the plan's); a missing summary is listed, not thrown.
SweepMerge merge_sweep(const std::filesystem::path& dir);

}  // namespace softcut::app
