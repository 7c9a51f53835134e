#include "bench/cut_steps.hpp"

#include <doctest/doctest.h>

#include "core/error.hpp"

using namespace softcut;

TEST_SUITE("bench/cut_steps") {
  TEST_CASE("the benchmark hook runs a small progressive cut and reports it") {
    const auto r = bench::cut_steps(4, 5);
    CHECK(r.region_tets == 6 * 64);
    CHECK(r.region_tets_after > r.region_tets);
    CHECK(r.steps == 5);
    CHECK(r.pieces_separated > 0);
    CHECK(r.mean_ms <= r.max_ms);
    CHECK(r.worst_dihedral_deg >= cut::CutOptions{}.min_dihedral_deg);
    // Half the box operational: fewer region tets, the cut still runs.
    const auto h = bench::cut_steps(4, 5, 0.5);
    CHECK(h.region_tets < r.region_tets);
    CHECK(h.region_tets_after > h.region_tets);
    CHECK_THROWS_AS(bench::cut_steps(0, 5), Error);
  }
}
