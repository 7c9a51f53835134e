#include "sim/tool_report.hpp"

#include <cmath>
#include <cstdio>

#include "core/warning.hpp"

namespace softcut::sim {

namespace {

std::string number(double v, const char* unit) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g %s", v, unit);
  return buf;
}

std::string pressure(double pa) {
  return pa >= 1e6 ? number(pa / 1e6, "MPa") : pa >= 1e3 ? number(pa / 1e3, "kPa") : number(pa, "Pa");
}

}  // namespace

std::vector<std::string> idle_tool_warnings(const Model& m, const State& s, bool complete) {
  std::vector<std::string> out;
  if (!complete) return out;
  for (size_t k = 0; k < s.tool_specs.size() && k < s.tools.size(); ++k) {
    const tools::ToolSpec& spec = s.tool_specs[k];
    const tools::ToolState& ts = s.tools[k];
    const std::string who = cat(spec.where.empty() ? "" : spec.where + ": ", tools::to_string(spec.kind), " '",
                                spec.name, "'");
    const bool scalpel = spec.kind == tools::ToolSpec::Kind::scalpel;
    if (!ts.was_active) {
      const double end = m.frame_time(s.frame);
      out.push_back(coded_warning(
          "tool_never_active",
          cat(who, " was never active: ",
              spec.start > end ? cat("its start = ", number(spec.start, "s"), " comes after the run's last "
                                           "frame at t = ", number(end, "s"), "; start it earlier or run longer")
                                     : std::string("it was switched off (f:enable_tool) for the whole run"))));
    } else if (!ts.touched) {
      const std::string closest =
          std::isfinite(ts.closest_gap)
              ? cat(" (closest ", number(ts.closest_gap * 1e3, "mm"), " at t = ", number(ts.closest_time, "s"), ")")
              : std::string();
      out.push_back(coded_warning(
          "tool_never_touched",
          cat(who, " never touched the tissue", closest,
              spec.kind == tools::ToolSpec::Kind::grasper ? ", so it never closed" : "",
              "; move its path onto the surface", scalpel ? "" : " or give it a larger radius")));
    } else if (scalpel && ts.cut_events == 0 && std::isfinite(spec.cut_pressure)) {
      const std::string why =
          ts.max_pressure < spec.cut_pressure
              ? cat("its contact pressure peaked at ", pressure(ts.max_pressure), " at t = ",
                    number(ts.max_pressure_time, "s"), ", below its cut_pressure = ", pressure(spec.cut_pressure),
                    "; press harder (force or stiffness) or lower cut_pressure")
              : cat("it reached its cut_pressure = ", pressure(spec.cut_pressure), " but its blade crossed no tissue "
                    "it may cut (only the s:operational{} region is cut)");
      out.push_back(coded_warning("scalpel_never_cut", cat(who, " touched the tissue but never cut: ", why)));
    }
  }
  return out;
}

}  // namespace softcut::sim
