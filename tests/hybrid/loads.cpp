#include "hybrid/loads.hpp"

#include <doctest/doctest.h>

#include <random>

#include "fixtures.hpp"

using namespace softcut;
using namespace softcut::hybrid;

TEST_SUITE("hybrid/loads") {
  TEST_CASE("check_load accepts sets 1, I, s and names the problem otherwise") {
    std::mt19937 rng(31);
    test::HybridCase c;
    do c = test::random_case(rng, 0); while (c.partition.interior.empty() || c.partition.interface.empty());
    const Partition& p = c.partition;
    const Eigen::Vector3d f(1, 2, 3);
    CHECK(check_load(p, p.surface[0], f) == NodeSet::surface);
    CHECK(check_load(p, p.interface[0], f) == NodeSet::interface);
    if (!p.operational.empty()) CHECK(check_load(p, p.operational[0], f) == NodeSet::operational);
    CHECK_THROWS_WITH_AS(check_load(p, p.interior[0], f, "probe"), doctest::Contains("probe on node"), Error);
    CHECK_THROWS_WITH_AS(check_load(p, p.interior[0], f), doctest::Contains("make the region around node"), Error);
    CHECK_THROWS_WITH_AS(check_load(p, p.fixed[0], f), doctest::Contains("is fixed"), Error);
    CHECK_THROWS_WITH_AS(check_load(p, p.num_nodes(), f), doctest::Contains("no such node"), Error);
    CHECK_THROWS_WITH_AS(check_load(p, p.surface[0], Eigen::Vector3d(0, INFINITY, 0)), doctest::Contains("NaN or Inf"),
                         Error);
  }
}
