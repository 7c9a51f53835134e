// engine/core/threads.cpp: the thread policy's count is at least one, and
// SingleThreadedBlas scopes, nested or overlapping on several threads, hold
// OpenBLAS at one thread until the last closes, then give back the count
// from before the first.
#include "core/threads.hpp"

#include <doctest/doctest.h>

#include <dlfcn.h>

#include <thread>

using namespace softcut;

TEST_SUITE("core/threads") {
  TEST_CASE("the policy gives at least one thread and says why") {
    CHECK(thread_policy().threads >= 1);
    CHECK(!thread_policy().reason.empty());
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
    apply_blas_threads(thread_policy().threads);
  }
}
