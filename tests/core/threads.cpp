// engine/core/threads.cpp: the thread policy's count is at least one, and
// SingleThreadedBlas scopes, nested or overlapping on several threads, hold
// OpenBLAS at one thread until the last closes, then give back the count
// from before the first.
#include "core/threads.hpp"

#include <doctest/doctest.h>

#include <dlfcn.h>

#include <cmath>
#include <thread>

using namespace softcut;

TEST_SUITE("core/threads") {
  TEST_CASE("the policy gives at least one thread and says why") {
    CHECK(thread_policy().threads >= 1);
    CHECK(thread_policy().blas_threads >= 1);
    CHECK(thread_policy().blas_threads <= thread_policy().threads);
    CHECK(!thread_policy().reason.empty());
  }

  TEST_CASE("idle cores for softcut, at most two of them for OpenBLAS unless SOFTCUT_THREADS says") {
    ThreadPolicy p = thread_policy_for(nullptr, 2, 0.1);
    CHECK(p.threads == 2);
    CHECK(p.blas_threads == 2);
    CHECK(p.reason == "2 cores, load 0.1: 2 idle");
    p = thread_policy_for(nullptr, 2, 1.7);  // another run on one core
    CHECK(p.threads == 1);
    CHECK(p.blas_threads == 1);
    p = thread_policy_for(nullptr, 16, 0);  // the H100 machine's: 16 OpenBLAS threads ran 6-24x slower
    CHECK(p.threads == 16);
    CHECK(p.blas_threads == kDefaultBlasThreads);
    CHECK(p.reason == "16 cores, load 0: 16 idle, BLAS on 2");
    p = thread_policy_for(nullptr, 4, 99);  // overloaded: still one
    CHECK(p.threads == 1);
    CHECK(p.blas_threads == 1);
    p = thread_policy_for("8", 16, 0);  // an explicit choice holds for both
    CHECK(p.threads == 8);
    CHECK(p.blas_threads == 8);
    CHECK(p.reason == "SOFTCUT_THREADS=8");
    p = thread_policy_for("8x", 16, 0);
    CHECK(p.threads == 16);
    CHECK(p.blas_threads == 2);
    CHECK(p.reason == "SOFTCUT_THREADS='8x' ignored (want 1..1024); 16 cores, load 0: 16 idle, BLAS on 2");
    p = thread_policy_for("0", 3, std::nan(""));
    CHECK(p.threads == 3);
    CHECK(p.blas_threads == 2);
  }

  TEST_CASE("single-threaded BLAS scopes overlap and restore the count from before the first") {
    // This binary does not link a BLAS; load the OpenBLAS that softcut's
    // CHOLMOD uses (scripts/install-deps.sh installs it) where dlsym finds it.
    REQUIRE(dlopen("libopenblas.so.0", RTLD_NOW | RTLD_GLOBAL) != nullptr);
    REQUIRE(blas_threads() > 0);
    apply_blas_threads(2);
    REQUIRE(blas_threads() == 2);
    {
      SingleThreadedBlas a;
      CHECK(blas_threads() == 1);
      std::thread other([] {
        SingleThreadedBlas b;
        CHECK(blas_threads() == 1);
      });
      {
        SingleThreadedBlas nested;
        CHECK(blas_threads() == 1);
      }
      CHECK(blas_threads() == 1);  // `a` is still open
      other.join();
      CHECK(blas_threads() == 1);
    }
    CHECK(blas_threads() == 2);
    apply_blas_threads(thread_policy().blas_threads);
  }
}
