#pragma once
// Run control: what a scenario's script may change between frames (through
// lua/wrap_frame, which only converts arguments), and the named numbers it
// records. The engine owns the State; these are the only writes a script
// makes to it. Each takes effect from the next frame (the one being
// finished is done). Tool and load indices are those of the spec
// (Model::spec.tools, .loads); an index out of range throws softcut::Error.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace softcut::sim {

struct State;

// Finish after this frame (summary: exit_reason "stopped").
void request_stop(State& s);
// Puts tool `tool`'s tip at `tip` (m) from the next frame on, overriding
// its path; nullopt returns it to its path.
void move_tool(State& s, int tool, const std::optional<Eigen::Vector3d>& tip);
// Switches tool `tool` on or off (off: no contact, no force; a grasper lets go).
void enable_tool(State& s, int tool, bool on);
// Multiplies load `load`'s ramp by `scale` and/or switches it.
void set_load(State& s, int load, std::optional<double> scale, std::optional<bool> enabled);

// A named number a scenario records (Frame:record): summary.json "metrics"
// and sweep.csv's metric.<name> columns (docs/outputs.md).
struct Metric {
  std::string name;
  double value = 0;            // the last recorded
  double min = 0, max = 0, sum = 0;
  int samples = 0;             // record calls
  int frame = -1;              // of the last
  double time = 0;             // s, of the last
};
// Most metric names a run may record, and the longest name.
constexpr std::size_t kMaxMetrics = 256;
constexpr std::size_t kMaxMetricName = 64;
// Records `value` under `name` at the state's frame. Throws softcut::Error
// for a name that is not 1..64 letters, digits, '_', '.' or '-' starting
// with a letter or '_' (it becomes a CSV column), a value that is not
// finite, or a 257th name.
void record_metric(State& s, std::string_view name, double value);

}  // namespace softcut::sim
