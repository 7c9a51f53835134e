#pragma once
// What a library call may do to the process's stop handlers, undone.
//
// METIS (CHOLMOD's fill-reducing ordering for large 3D systems) traps
// SIGTERM for the length of an ordering with signal() and puts the previous
// handler back with signal() too. On glibc that is sysv_signal: the handler
// comes back with SA_RESETHAND | SA_NODEFER, so after the first factor the
// run's stop handler (app/run_support.hpp SignalGuard) fires once and resets
// SIGTERM to its default: a second copy of the stop killed the run with
// status 143 and no message (docs/hardening.md #38.11; found with strace -k).
// Around such a call, KeepSignalActions restores SIGINT's and SIGTERM's
// actions exactly as they were, flags included.
#include <csignal>

namespace softcut {

class KeepSignalActions {
 public:
  KeepSignalActions();
  ~KeepSignalActions();
  KeepSignalActions(const KeepSignalActions&) = delete;
  KeepSignalActions& operator=(const KeepSignalActions&) = delete;

 private:
  struct sigaction int_ {}, term_{};
};

}  // namespace softcut
