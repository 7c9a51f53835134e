#pragma once
// A wall-clock limit for one run (`softcut run --timeout SECONDS`): what the
// instruction count cannot see (a long C call, a blocking read) still ends.
// At the deadline the watchdog sets expired(), which the Lua hook and the
// frame loop poll: the run stops and finishes its outputs, reason "timeout".
// If the process is still inside the run `grace_s` later (stuck in native
// code where nothing polls), it prints `message` and ends the process with
// exit status 124, as timeout(1) does: outputs are then left unfinished.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace softcut {

class Watchdog {
 public:
  // seconds <= 0: no limit (expired() stays false, no thread).
  Watchdog(double seconds, double grace_s, std::string message);
  ~Watchdog();  // cancels
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

  const std::atomic<bool>& expired() const { return expired_; }
  double seconds() const { return seconds_; }
  // Time until the deadline, s (negative past it; infinite without a limit).
  double seconds_left() const;

 private:
  double seconds_, grace_s_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::string message_;
  std::atomic<bool> expired_{false};
  std::mutex mutex_;
  std::condition_variable cancelled_;
  bool done_ = false;
  std::thread thread_;
};

}  // namespace softcut
