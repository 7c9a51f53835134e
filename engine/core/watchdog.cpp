#include "core/watchdog.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>

namespace softcut {

Watchdog::Watchdog(double seconds, double grace_s, std::string message)
    : seconds_(seconds), grace_s_(grace_s), message_(std::move(message)) {
  if (!(seconds > 0)) return;
  thread_ = std::thread([this] {
    using dsec = std::chrono::duration<double>;
    std::unique_lock lock(mutex_);
    if (cancelled_.wait_for(lock, dsec(seconds_), [this] { return done_; })) return;
    expired_ = true;
    if (cancelled_.wait_for(lock, dsec(grace_s_), [this] { return done_; })) return;
    // Nothing polled the flag: end the process (no destructor or atexit
    // handler runs; they might wait on the stuck thread).
    std::fprintf(stderr, "softcut: error: %s\n", message_.c_str());
    std::fflush(stderr);
    ::_exit(124);
  });
}

double Watchdog::seconds_left() const {
  if (!(seconds_ > 0)) return HUGE_VAL;
  return seconds_ - std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

Watchdog::~Watchdog() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard lock(mutex_);
    done_ = true;
  }
  cancelled_.notify_all();
  thread_.join();
}

}  // namespace softcut
