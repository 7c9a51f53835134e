#pragma once
// The frame loop behind `softcut run`: step, record, call the script, report
// progress, honour interruption (Ctrl-C) and script stop requests.
#include <atomic>
#include <cmath>
#include <functional>
#include <string>

#include "sim/expectations.hpp"
#include "sim/model.hpp"

namespace softcut::sim {

class Recorder;

// completed: all frames; frame_limit: RunHooks::max_frames reached; stopped:
// by the script; interrupted: by the interrupt flag; error: an exception.
enum class ExitReason { completed, frame_limit, stopped, interrupted, timeout, error };
const char* to_string(ExitReason r);

struct RunHooks {
  // After each recorded frame, before on_frame: a check function's verdict
  // for expectation `index` when it is due (sim/expectations.hpp).
  ExpectationCheck check;
  // After each recorded frame (the Lua on_frame): may read the state, move
  // tools, change loads; return false (or set s.stop_requested) to stop.
  std::function<bool(const Model&, State&)> on_frame;
  // frame = index just completed, of num_frames; elapsed wall time, s.
  std::function<void(int frame, int num_frames, double elapsed_s)> progress;
  // Set by the CLI's signal handler: the current frame is finished and
  // recorded, then the run ends with ExitReason::interrupted.
  const std::atomic<bool>* interrupt = nullptr;
  // Set by the run's wall-clock watchdog (core/watchdog.hpp): the run ends
  // with ExitReason::timeout, like an interrupt. A hook that fails while
  // either flag is set (a script stopped inside on_frame) ends the run the
  // same way, not as an error.
  const std::atomic<bool>* timed_out = nullptr;
  // Seconds left until that deadline when the loop starts (infinite: none).
  // Once the frames made so far show that the rest cannot finish in time
  // (projected at more than 1.5x what is left, after 2 s of frames), the run
  // ends at once as a timeout, saying so, instead of computing until the
  // deadline: 1e7 frames of a small box took hours.
  double seconds_left = HUGE_VAL;
  int max_frames = -1;  // >= 0: stop after this many frames (CLI --frames)
};

struct RunResult {
  int frames = 0;             // frames completed and recorded
  ExitReason reason = ExitReason::completed;
  std::string message;        // error text when reason == error; why, for a timeout foreseen
  double wall_s = 0.0;
};

// Runs frames s.frame + 1 .. m.num_frames - 1. Finishes `rec` (CSV renamed
// into place, PVD and summary.json written) in every case; on an exception
// from a step or hook it finishes with ExitReason::error and rethrows.
RunResult run(const Model& m, State& s, Recorder& rec, const RunHooks& hooks);

}  // namespace softcut::sim
