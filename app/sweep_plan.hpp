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
// Most swept parameters, and values in all (runs x parameters): the plan and
// the merged table stay a few tens of MB.
constexpr std::size_t kMaxSweepKeys = 100;
constexpr std::size_t kMaxSweepValues = 1000000;
// Longest parameter value, bytes: each becomes one `--set key=value`
// argument of a run (Linux refuses an argument over 128 KiB), a plan entry
// and a table cell.
constexpr std::size_t kMaxValueBytes = 4096;
// Largest sweep_plan.json read back, bytes.
constexpr std::size_t kMaxPlanBytes = std::size_t(64) << 20;

// Why `value` cannot be a parameter value, or "" when it can: it must be
// UTF-8 text (two different byte strings must not read alike in the plan,
// the table and the rerun command line) without control characters (a tab
// or line break may stand in a quoted field), of at most kMaxValueBytes,
// and not empty.
std::string bad_value(const std::string& value);

// `--grid key=v1,v2,...` arguments, in order: the Cartesian product, the last
// key varying fastest. Throws UsageError naming the bad argument (no '=', an
// empty value list, a key given twice, a key that is not a name, a bad
// value, too many runs).
std::vector<SweepRun> expand_grid(const std::vector<std::string>& grids, std::vector<std::string>& keys);
// A CSV table: a header of keys, one run per row (RFC 4180 quoting; blank
// lines and lines starting with '#' are skipped). Throws Error naming
// file:line for ragged rows, bad keys or values, unterminated quotes, too
// many runs.
std::vector<SweepRun> read_table(const std::filesystem::path& csv, std::vector<std::string>& keys);
// Gives each run its id: "run_" and the index, zero-padded to 4 digits (more
// when there are over 10000 runs).
void number_runs(std::vector<SweepRun>& runs);

// sweep_plan.json (nlohmann-json, keys sorted: byte-identical for equal plans).
std::string plan_json(const SweepPlan& plan);
// Reads it back from `dir`/sweep_plan.json (not through a link there; at
// most 64 MiB, the bounds above, run ids as number_runs gives them, every
// run with a value per key); throws Error naming the file and the field for
// anything malformed.
SweepPlan read_plan(const std::filesystem::path& dir);
// The same from the plan's text (`file` names it in messages).
SweepPlan parse_plan(const std::string& text, const std::string& file);

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
