// engine/core/helper_thread.cpp: each half runs exactly once, half 0 on the
// caller; the helper takes half 1 when it is awake, and the caller finishes
// alone when it is not; destruction never hangs, asleep or spinning.
#include "core/helper_thread.hpp"

#include <doctest/doctest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <thread>

using softcut::HelperThread;

TEST_SUITE("core/helper_thread") {
  TEST_CASE("every job runs each half exactly once, half 0 on the caller") {
    HelperThread h;
    const std::thread::id caller = std::this_thread::get_id();
    for (int job = 0; job < 20000; ++job) {
      if (job % 7 == 0) h.wake();
      std::array<std::atomic<int>, 2> runs{};
      std::atomic<int> others{0};
      bool half0_on_caller = false;
      h.run_halves([&](int half) {
        if (half != 0 && half != 1) return void(others.fetch_add(1));
        if (half == 0) half0_on_caller = std::this_thread::get_id() == caller;
        runs[size_t(half)].fetch_add(1);
      });
      REQUIRE(others.load() == 0);
      REQUIRE(runs[0].load() == 1);
      REQUIRE(runs[1].load() == 1);
      REQUIRE(half0_on_caller);
    }
  }

  TEST_CASE("an awake helper takes the second half while the caller works on the first") {
    HelperThread h;
    const std::thread::id caller = std::this_thread::get_id();
    bool helped = false;
    for (int attempt = 0; attempt < 200 && !helped; ++attempt) {
      h.wake();
      std::thread::id second;
      h.run_halves([&](int half) {
        if (half == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        else second = std::this_thread::get_id();
      });
      helped = second != caller;
    }
    CHECK(helped);
    CHECK(h.helped() > 0);
  }

  TEST_CASE("a sleeping helper is woken by a job, and the caller never waits for one that is not there") {
    HelperThread h;
    // Past the spin time the helper sleeps on its futex.
    std::this_thread::sleep_for(std::chrono::microseconds(20 * HelperThread::kSpinMicroseconds));
    int sum = 0;
    for (int job = 0; job < 100; ++job) {
      std::array<int, 2> v{};
      h.run_halves([&](int half) { v[size_t(half)] = half + 1; });
      sum += v[0] + v[1];
      if (job % 10 == 0) std::this_thread::sleep_for(std::chrono::microseconds(2 * HelperThread::kSpinMicroseconds));
    }
    CHECK(sum == 300);
  }

  TEST_CASE("left to the helper (tests' hook), every item the caller has not started runs on the helper") {
    HelperThread h;
    h.leave_to_helper(true);
    const std::thread::id caller = std::this_thread::get_id();
    for (int job = 0; job < 50; ++job) {
      // Asleep past its spin time, or spinning: the job wakes it either way.
      if (job % 2) std::this_thread::sleep_for(std::chrono::microseconds(3 * HelperThread::kSpinMicroseconds));
      std::array<std::thread::id, 2> ran{};
      h.run_halves([&](int half) { ran[size_t(half)] = std::this_thread::get_id(); });
      REQUIRE(ran[0] == caller);
      REQUIRE(ran[1] != caller);
      std::array<std::thread::id, 5> items{};
      h.run_items(5, [&](int item) { items[size_t(item)] = std::this_thread::get_id(); });
      for (const auto& id : items) REQUIRE((id != caller && id != std::thread::id{}));
    }
    CHECK(h.helped() == 50 * 6);
    h.leave_to_helper(false);
  }

  TEST_CASE("a job of items runs each exactly once, whoever claims them") {
    HelperThread h;
    for (int job = 0; job < 5000; ++job) {
      if (job % 3 == 0) h.wake();
      const int count = job % 17;  // 0 .. 16 items
      std::array<std::atomic<int>, 16> runs{};
      std::atomic<int> others{0};
      h.run_items(count, [&](int item) {
        if (item < 0 || item >= count) return void(others.fetch_add(1));
        runs[size_t(item)].fetch_add(1);
      });
      REQUIRE(others.load() == 0);
      for (int k = 0; k < 16; ++k) REQUIRE(runs[size_t(k)].load() == (k < count ? 1 : 0));
    }
  }

  TEST_CASE("a helper stuck in its item holds the caller up by that item only") {
    // The helper's item waits until the caller has run every other item:
    // this returns only if the caller claims them all while the helper holds one.
    HelperThread h;
    const std::thread::id caller = std::this_thread::get_id();
    bool helped = false;
    for (int attempt = 0; attempt < 200 && !helped; ++attempt) {
      h.wake();
      std::atomic<int> by_caller{0}, by_helper{0};
      h.run_items(10, [&](int) {
        if (std::this_thread::get_id() == caller) {  // slow enough for an awake helper to claim one
          std::this_thread::sleep_for(std::chrono::microseconds(200));
          return void(by_caller.fetch_add(1));
        }
        by_helper.fetch_add(1);
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (by_caller.load() + by_helper.load() < 10 && std::chrono::steady_clock::now() < until)
          std::this_thread::yield();
      });
      REQUIRE(by_caller.load() + by_helper.load() == 10);
      if (by_helper.load() > 0) {
        CHECK(by_helper.load() == 1);
        helped = true;
      }
    }
    CHECK(helped);
  }

  TEST_CASE("destroyed while asleep, while spinning, and right after a job: no hang") {
    { HelperThread h; }
    {
      HelperThread h;
      h.wake();
    }
    {
      HelperThread h;
      std::this_thread::sleep_for(std::chrono::microseconds(5 * HelperThread::kSpinMicroseconds));
    }
    {
      HelperThread h;
      int x = 0;
      h.run_halves([&](int half) {
        if (half == 1) x = 1;
      });
      CHECK(x == 1);
    }
  }
}
