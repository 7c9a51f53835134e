#include "sim/tool_log.hpp"

#include <algorithm>
#include <cstdio>

#include "sim/cutting.hpp"

namespace softcut::sim {

const char* const kToolLogHeader = "frame,time,tool,kind,engaged,nodes,fx,fy,fz,pressure,cut\n";

Eigen::Vector3d applied_tool_force(const Model& m, const State& s, int k) {
  const tools::ToolState& ts = s.tools[std::size_t(k)];
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < ts.nodes.size() && i < ts.forces.size(); ++i)
    if (!is_fixed_node(m, s, ts.nodes[i]) && !is_held_node(s, ts.nodes[i])) f += ts.forces[i];
  return f;
}

std::string tool_log_rows(const Model& m, const State& s) {
  std::string rows;
  char buf[512];
  for (std::size_t k = 0; k < s.tool_specs.size() && k < s.tools.size(); ++k) {
    const tools::ToolSpec& spec = s.tool_specs[k];
    const tools::ToolState& ts = s.tools[k];
    const Eigen::Vector3d f = applied_tool_force(m, s, int(k));
    const bool scalpel = spec.kind == tools::ToolSpec::Kind::scalpel;
    // Tool names are the script's: quoted as CSV needs when they hold a
    // comma, a quote or a line break.
    std::string name = spec.name;
    if (name.find_first_of(",\"\r\n") != std::string::npos) {
      std::string q = "\"";
      for (char c : name) q += c == '"' ? std::string("\"\"") : std::string(1, c);
      name = q + "\"";
    }
    const int len = std::snprintf(buf, sizeof buf, "%d,%.9e,", s.frame, s.time);
    rows.append(buf, std::size_t(len));
    rows += name;
    const int len2 = std::snprintf(buf, sizeof buf, ",%s,%d,%zu,%.9e,%.9e,%.9e,%.9e,%d\n", tools::to_string(spec.kind),
                                   int(ts.engaged), ts.nodes.size(), f.x(), f.y(), f.z(), scalpel ? ts.pressure : 0.0,
                                   int(scalpel && ts.cutting));
    rows.append(buf, std::size_t(len2));
  }
  return rows;
}

void ToolStatistics::add(const Model& m, const State& s) {
  for (std::size_t k = 0; k < s.tool_specs.size() && k < s.tools.size(); ++k) {
    if (tools_.size() <= k) tools_.push_back({s.tool_specs[k].name, tools::to_string(s.tool_specs[k].kind)});
    ToolRunStats& t = tools_[k];
    const tools::ToolState& ts = s.tools[k];
    if (s.tool_specs[k].kind == tools::ToolSpec::Kind::scalpel) {
      t.peak_pressure = std::max(t.peak_pressure, ts.pressure);
      t.frames_cut += ts.cutting;
    }
    if (!ts.engaged) continue;
    const double f = applied_tool_force(m, s, int(k)).norm();
    ++t.frames_engaged;
    t.peak_force = std::max(t.peak_force, f);
    t.force_sum += f;
  }
}

Json ToolStatistics::json() const {
  Json list = Json::array();
  for (const ToolRunStats& t : tools_) {
    Json j = {{"name", t.name}, {"kind", t.kind}, {"frames_engaged", t.frames_engaged},
              {"peak_force_n", json_number(t.peak_force)},
              {"mean_force_n", json_number(t.frames_engaged ? t.force_sum / t.frames_engaged : 0.0)}};
    if (t.kind == "scalpel") {
      j["peak_pressure_pa"] = json_number(t.peak_pressure);
      j["frames_cut"] = t.frames_cut;
    }
    list.push_back(std::move(j));
  }
  return list;
}

}  // namespace softcut::sim
