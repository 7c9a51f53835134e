#pragma once
// Pieces shared by `softcut run` and `softcut check`: --set parsing, the
// progress display, and the SIGINT/SIGTERM flag the frame loop polls.
#include <atomic>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "sim/scenario_spec.hpp"

namespace softcut::app {

// Every parse failure below is a softcut::UsageError (exit status 2).
// "key=value" -> overrides[key] = value; throws on a malformed pair.
void add_override(std::map<std::string, std::string>& overrides, const std::string& pair);
// --backend value: auto|cpu|gpu|direct|monolithic, else throws listing them.
backend::Backend parse_backend(const std::string& text);
// A non-negative integer option value; throws naming the option.
int parse_count(const std::string& text, const char* option);
// The value of -j/--jobs: at least 1; throws naming `command` ("softcut check").
int parse_jobs(const std::string& text, const char* command);
// Seconds (>= 0; 0: no limit); throws naming the option.
double parse_seconds(const std::string& text, const char* option);
// Bytes with an optional K/M/G suffix (0: no limit); throws naming the option.
std::uint64_t parse_bytes(const std::string& text, const char* option);
// "WxH" (pixels, 1..16384 each) -> {W, H}; throws naming the option.
std::pair<int, int> parse_size(const std::string& text, const char* option);

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
