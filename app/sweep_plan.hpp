#pragma once
// What `softcut sweep` runs: the parameter combinations of a grid or a table,
// each a run with a stable id ("run_0003": its index in the expansion) and
// folder (DIR/run_0003/), and the slice of them one shard runs. Every shard
// writes the same plan to DIR/sweep_plan.json, and `sweep merge` reads it to
// know which runs must be there (docs/sweeps.md).
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace softcut::app {

struct SweepRun {
  std::string id;                                          // "run_0003"
  std::vector<std::pair<std::string, std::string>> params;  // key -> value, in the plan's key order
};

struct SweepPlan {
  std::string scenario;                 // absolute, normal form
  std::vector<std::string> run_options;  // passed to every `softcut run` (--frames 5, --set k=v, ...)
  std::vector<std::string> keys;         // swept parameters, in column order
  std::vector<SweepRun> runs;
};

// Most runs one sweep may expand to: a typo in a grid (or a hostile table)
// must not try to list a billion folders.
constexpr std::size_t kMaxSweepRuns = 100000;

// `--grid key=v1,v2,...` arguments, in order: the Cartesian product, the last
// key varying fastest. Throws UsageError naming the bad argument (no '=', an
// empty value list, a key given twice, a key that is not a name, too many runs).
std::vector<SweepRun> expand_grid(const std::vector<std::string>& grids, std::vector<std::string>& keys);
// A CSV table: a header of keys, one run per row (RFC 4180 quoting; blank
// lines and lines starting with '#' are skipped). Throws Error naming
// file:line for ragged rows, bad keys, unterminated quotes, too many runs.
std::vector<SweepRun> read_table(const std::filesystem::path& csv, std::vector<std::string>& keys);
// Gives each run its id: "run_" and the index, zero-padded to 4 digits (more
// when there are over 10000 runs).
void number_runs(std::vector<SweepRun>& runs);

// sweep_plan.json (nlohmann-json, keys sorted: byte-identical for equal plans).
std::string plan_json(const SweepPlan& plan);
// Reads it back; throws Error naming the file for anything malformed.
SweepPlan read_plan(const std::filesystem::path& file);

struct Shard {
  int index = 0, count = 1;  // runs i with i % count == index
  std::string source;        // "--shard 1/3", "SLURM_ARRAY_TASK_ID=4 (min 3, count 3)", "" (all runs)
};
// `--shard I/N` when given ("I/N", 0 <= I < N); else the scheduler's
// environment: SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN of
// SLURM_ARRAY_TASK_COUNT, or JOB_COMPLETION_INDEX (Kubernetes indexed Jobs)
// of `shards` (--shards N, required with it); else every run. `getenv` is
// injectable for tests. Throws UsageError for malformed or inconsistent values.
Shard choose_shard(const std::optional<std::string>& shard_arg, std::optional<int> shards,
                   const std::function<const char*(const char*)>& getenv);
// Indices of the runs this shard runs, in order.
std::vector<std::size_t> shard_runs(std::size_t num_runs, const Shard& shard);

}  // namespace softcut::app
