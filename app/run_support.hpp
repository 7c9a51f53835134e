#pragma once
// Pieces shared by `softcut run`, `check` and `sweep`: --set pairs, the
// progress display, and the SIGINT/SIGTERM flag the frame loop polls.
#include <atomic>
#include <map>
#include <string>
#include <vector>

namespace softcut::app {

// Why a run that warned fails under --warnings-as-errors: "N warning(s) with
// --warnings-as-errors: the first, ..." (each warning keeps its [code]).
std::string warned_message(const std::vector<std::string>& warnings);

// "key=value" -> overrides[key] = value (the value may hold '='); throws
// UsageError on a malformed pair (--set checks it first: key_value()).
void add_override(std::map<std::string, std::string>& overrides, const std::string& pair);

// Progress of a run on stderr: a bar with ETA on a terminal, a plain line
// about every 10% otherwise, nothing when quiet.
class Progress {
 public:
  enum class Mode { quiet, bar, lines };
  explicit Progress(Mode m) : mode_(m) {}
  void update(int frame, int num_frames, double elapsed_s);
  void done();  // ends the bar's line

 private:
  Mode mode_;
  int last_decile_ = -1;
  double last_draw_s_ = -1.0;  // bar: redrawn at most every 0.1 s (and at the end)
  bool drawn_ = false;
};

// Installs SIGINT/SIGTERM handlers that set flag() while it lives; restores
// the previous handlers on destruction.
class SignalGuard {
 public:
  SignalGuard();
  ~SignalGuard();
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;
  static std::atomic<bool>& flag();
};

}  // namespace softcut::app
