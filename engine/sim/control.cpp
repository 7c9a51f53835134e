#include "sim/control.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/error.hpp"
#include "sim/model.hpp"

namespace softcut::sim {

namespace {

template <class T>
T& at(std::vector<T>& list, int i, const char* what) {
  if (i < 0 || size_t(i) >= list.size()) fail(what, " ", i, " out of range (the scenario has ", list.size(), ")");
  return list[size_t(i)];
}

bool valid_name(std::string_view n) {
  if (n.empty() || n.size() > kMaxMetricName) return false;
  if (!(std::isalpha((unsigned char)n[0]) || n[0] == '_')) return false;
  return std::all_of(n.begin(), n.end(),
                     [](char c) { return std::isalnum((unsigned char)c) || c == '_' || c == '.' || c == '-'; });
}

}  // namespace

void request_stop(State& s) { s.stop_requested = true; }

void move_tool(State& s, int tool, const std::optional<Eigen::Vector3d>& tip) {
  tools::ToolState& t = at(s.tools, tool, "tool");
  if (tip && !tip->allFinite()) fail("move_tool: the tip is not finite");
  t.override_tip = bool(tip);
  if (tip) t.tip = *tip;
}

void enable_tool(State& s, int tool, bool on) { at(s.tool_specs, tool, "tool").enabled = on; }

void set_load(State& s, int load, std::optional<double> scale, std::optional<bool> enabled) {
  ActiveLoad& l = at(s.loads, load, "load");
  if (scale && !std::isfinite(*scale)) fail("set_load: load '", l.spec.name, "': the scale is not finite");
  if (scale) l.scale = *scale;
  if (enabled) l.enabled = *enabled;
}

void record_metric(State& s, std::string_view name, double value) {
  if (!valid_name(name))
    fail("record: metric name '", std::string(name.substr(0, 80)), "' is not 1 to ", kMaxMetricName,
         " letters, digits, '_', '.' or '-' starting with a letter or '_' (it names a sweep.csv column)");
  if (!std::isfinite(value)) fail("record: metric '", std::string(name), "' is ", value, ", not a finite number");
  auto it = std::find_if(s.metrics.begin(), s.metrics.end(), [&](const Metric& m) { return m.name == name; });
  if (it == s.metrics.end()) {
    if (s.metrics.size() >= kMaxMetrics)
      fail("record: metric '", std::string(name), "' would be the ", kMaxMetrics + 1, "th name; a run records at most ",
           kMaxMetrics);
    s.metrics.push_back(Metric{std::string(name), value, value, value, 0, 0, -1, 0});
    it = s.metrics.end() - 1;
  }
  it->value = value;
  it->min = std::min(it->min, value), it->max = std::max(it->max, value);
  it->sum += value;
  it->samples++;
  it->frame = s.frame, it->time = s.time;
}

}  // namespace softcut::sim
