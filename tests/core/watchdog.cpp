// engine/core/watchdog.cpp: the wall-clock limit sets its flag at the
// deadline; a run that does not stop within the grace time is ended with
// exit status 124 and the message.
#include "core/watchdog.hpp"

#include <doctest/doctest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <thread>

TEST_SUITE("core/watchdog") {
  TEST_CASE("no limit: never expires - cancelled before the deadline: never expires") {
    softcut::Watchdog none(0, 1, "x");
    CHECK_FALSE(none.expired());
    { softcut::Watchdog w(60, 1, "x"); }  // destruction cancels at once (no 60 s wait)
  }

  TEST_CASE("expires at the deadline and is polled") {
    softcut::Watchdog w(0.05, 30, "x");
    for (int i = 0; i < 400 && !w.expired(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    CHECK(w.expired());
  }

  TEST_CASE("a run stuck past the grace time ends the process with status 124") {
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
      softcut::Watchdog w(0.05, 0.05, "stuck for the test");
      ::sleep(30);  // never polls
      ::_exit(0);
    }
    int st = 0;
    ::waitpid(pid, &st, 0);
    CHECK(WIFEXITED(st));
    CHECK(WEXITSTATUS(st) == 124);
  }
}
