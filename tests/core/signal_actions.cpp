// core/signal_actions: a library that re-installs a stop handler with other
// flags (METIS through CHOLMOD's ordering: sysv_signal, SA_RESETHAND) is
// undone. The real thing is in tests/solve/cholesky.cpp.
#include "core/signal_actions.hpp"

#include <doctest/doctest.h>

#include <csignal>
#include <initializer_list>

using namespace softcut;

namespace {

extern "C" void mine(int) {}
extern "C" void theirs(int) {}

struct Installed {
  struct sigaction old_int {}, old_term{};
  Installed() {
    struct sigaction sa {};
    sa.sa_handler = mine;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
  }
  ~Installed() {
    sigaction(SIGINT, &old_int, nullptr);
    sigaction(SIGTERM, &old_term, nullptr);
  }
};

struct sigaction current(int sig) {
  struct sigaction now {};
  sigaction(sig, nullptr, &now);
  return now;
}

}  // namespace

TEST_SUITE("core/signal_actions") {
  TEST_CASE("a handler re-installed with SysV flags inside the scope comes back as it was") {
    const Installed ours;
    {
      const KeepSignalActions keep;
      sysv_signal(SIGTERM, theirs);  // what METIS's gk_sigtrap does
      sysv_signal(SIGTERM, mine);    // and gk_siguntrap: ours, but SA_RESETHAND
      sysv_signal(SIGINT, theirs);
      CHECK((current(SIGTERM).sa_flags & SA_RESETHAND) != 0);
    }
    for (int sig : {SIGINT, SIGTERM}) {
      CAPTURE(sig);
      const struct sigaction now = current(sig);
      const bool ours_again = now.sa_handler == mine;
      CHECK(ours_again);
      CHECK((now.sa_flags & (SA_RESETHAND | SA_NODEFER)) == 0);
    }
  }
}
