// engine/core/output_budget.cpp: the run's bound on bytes written.
#include "core/output_budget.hpp"

#include <doctest/doctest.h>

#include <thread>
#include <vector>

#include "core/error.hpp"

TEST_SUITE("core/output_budget") {
  TEST_CASE("charges up to the limit, refuses past it (naming --max-output), counts nothing refused") {
    softcut::OutputBudget b(100);
    b.charge(60, "a");
    b.charge(40, "b");
    CHECK(b.used() == 100);
    CHECK_THROWS_WITH_AS(b.charge(1, "frame_000003.png"), doctest::Contains("frame_000003.png"), softcut::Error);
    CHECK_THROWS_WITH_AS(b.charge(~0ull, "x"), doctest::Contains("--max-output"), softcut::Error);
    CHECK(b.used() == 100);
  }

  TEST_CASE("unlimited with 0 - exact under concurrent charges") {
    softcut::OutputBudget none(0);
    none.charge(~0ull / 2, "big");
    CHECK(none.used() == ~0ull / 2);
    softcut::OutputBudget b(1000);
    std::vector<std::thread> ts;
    std::atomic<int> refused{0};
    for (int t = 0; t < 4; ++t)
      ts.emplace_back([&] {
        for (int i = 0; i < 500; ++i) try {
            b.charge(1, "x");
          } catch (const softcut::Error&) {
            refused++;
          }
      });
    for (auto& t : ts) t.join();
    CHECK(b.used() == 1000);
    CHECK(refused == 1000);
  }
}
