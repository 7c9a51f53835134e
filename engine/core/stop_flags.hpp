#pragma once
// Requests from outside to stop long engine work: Ctrl-C / SIGTERM (the
// CLI's signal handler) and the run's wall-clock watchdog. The Lua hook and
// the frame loop poll them; so does work that runs before the frame loop
// and may take long (the hybrid precompute's assembly and column blocks),
// between pieces of at most about 0.1 s each, so a stop is honoured
// promptly there too. A piece of work that cannot be split (CHOLMOD's
// factorization) finishes first.
#include <atomic>

#include "core/error.hpp"

namespace softcut {

// Ctrl-C / SIGTERM ended the work: the CLI exits 130 for it, as for an
// interrupted frame loop.
class InterruptedError : public Error {
 public:
  using Error::Error;
};

struct StopFlags {
  const std::atomic<bool>* interrupt = nullptr;  // SIGINT / SIGTERM
  const std::atomic<bool>* deadline = nullptr;   // the watchdog fired (core/watchdog.hpp)

  bool requested() const {
    return (interrupt && interrupt->load(std::memory_order_relaxed)) ||
           (deadline && deadline->load(std::memory_order_relaxed));
  }
  // Throws InterruptedError or TimeoutError, naming `what` (the work
  // stopped), when either flag is set.
  void poll(const char* what) const {
    if (interrupt && interrupt->load(std::memory_order_relaxed))
      throw InterruptedError(cat(what, ": interrupted"));
    if (deadline && deadline->load(std::memory_order_relaxed))
      throw TimeoutError(cat(what, ": the wall-clock limit (--timeout) was reached"));
  }
};

}  // namespace softcut
