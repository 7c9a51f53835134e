#include "sim/run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

#include "core/error.hpp"

#include "core/timer.hpp"
#include "sim/outputs.hpp"
#include "sim/step.hpp"
#include "sim/tool_report.hpp"
#include "sim/validity.hpp"

namespace softcut::sim {

const char* to_string(ExitReason r) {
  switch (r) {
    case ExitReason::completed: return "completed";
    case ExitReason::frame_limit: return "frame_limit";
    case ExitReason::stopped: return "stopped";
    case ExitReason::interrupted: return "interrupted";
    case ExitReason::timeout: return "timeout";
    case ExitReason::error: return "error";
  }
  return "?";
}

RunResult run(const Model& m, State& s, Recorder& rec, const RunHooks& hooks) {
  Timer wall;
  RunResult r;
  int last = m.num_frames - 1;
  if (hooks.max_frames >= 0 && s.frame + hooks.max_frames < last) {
    last = s.frame + hooks.max_frames;
    r.reason = ExitReason::frame_limit;
  }
  // An interrupt or the deadline ends the run after the frame in progress.
  auto stop_reason = [&](ExitReason& why) {
    if (hooks.interrupt && hooks.interrupt->load()) why = ExitReason::interrupted;
    else if (hooks.timed_out && hooks.timed_out->load()) why = ExitReason::timeout;
    else return false;
    return true;
  };
  // The frames left cannot be made before the deadline: stop now (see RunHooks::seconds_left).
  constexpr double kSettle = 2.0, kMargin = 1.5;
  double next_projection = kSettle;
  auto foreseen_timeout = [&] {
    const double elapsed = wall.seconds();
    if (!std::isfinite(hooks.seconds_left) || elapsed < next_projection || r.frames < 2) return false;
    next_projection = elapsed + 1.0;
    const double per_frame = elapsed / r.frames, left = per_frame * (last - s.frame);
    if (!(left > kMargin * (hooks.seconds_left - elapsed))) return false;
    r.reason = ExitReason::timeout;
    char when[64];
    std::snprintf(when, sizeof when, left >= 7200 ? "%.1f h" : left >= 120 ? "%.0f min" : "%.0f s",
                  left >= 7200 ? left / 3600 : left >= 120 ? left / 60 : left);
    char ms[32];
    std::snprintf(ms, sizeof ms, "%.2g", per_frame * 1e3);
    r.message = cat("at ", ms, " ms per frame the ", last - s.frame,
                    " frames left would take about ", when, ", past the wall-clock limit (--timeout) in ",
                    std::round(std::max(0.0, hooks.seconds_left - elapsed)), " s: stopped now; lower fps or duration, "
                    "stop earlier with --frames N, or raise --timeout");
    return true;
  };
  // What the run did not do is said before its outputs are written (tools
  // that never touched: sim/tool_report.hpp), so summary.json has it too.
  auto finish = [&] {
    mark_unreached_expectations(m, s);
    const bool complete = r.reason == ExitReason::completed || r.reason == ExitReason::stopped;
    for (std::string& w : idle_tool_warnings(m, s, complete)) s.warnings.push_back(std::move(w));
    for (std::string& w : validity_warnings(m, s)) s.warnings.push_back(std::move(w));
    rec.finish(m, s, r);
  };
  try {
    while (s.frame < last) {
      if (stop_reason(r.reason) || foreseen_timeout()) break;
      step(m, s);
      rec.record(m, s);
      r.frames++;
      check_due_expectations(m, s, hooks.check);
      const bool go_on = hooks.on_frame ? hooks.on_frame(m, s) : true;
      if (hooks.progress) hooks.progress(s.frame, m.num_frames, wall.seconds());
      if (stop_reason(r.reason)) break;
      if (!go_on || s.stop_requested) {
        r.reason = ExitReason::stopped;
        break;
      }
    }
  } catch (const std::exception& e) {
    r.message = e.what();
    r.wall_s = wall.seconds();
    if (stop_reason(r.reason)) {  // the stop reached the script inside on_frame: not an error
      finish();
      return r;
    }
    r.reason = ExitReason::error;
    try {
      finish();
    } catch (...) {
      // The run's own error is the one to report (a render failure, if any, is in the summary).
    }
    throw;
  }
  r.wall_s = wall.seconds();
  finish();
  return r;
}

}  // namespace softcut::sim
