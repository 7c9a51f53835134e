#include "mesh/generate/box.hpp"

#include <doctest/doctest.h>

#include "generate_checks.hpp"

using namespace softcut;
using namespace softcut::mesh;

TEST_SUITE("mesh/generate/box") {
  TEST_CASE("closed, positive, exact volume over resolutions and jitter") {
    for (int n : {1, 2, 3})
      for (double jitter : {0.0, 0.2})
        for (unsigned seed : {1u, 7u}) {
          BoxOptions o;
          o.max_corner = Eigen::Vector3d(0.03, 0.02, 0.01);
          o.nx = n + 1, o.ny = n, o.nz = 2 * n;
          o.jitter = jitter, o.seed = seed;
          const TetMesh m = generate_box(o);
          CAPTURE(n);
          CAPTURE(jitter);
          CHECK(m.num_tets() == 6 * o.nx * o.ny * o.nz);
          CHECK(m.num_nodes() == (o.nx + 1) * (o.ny + 1) * (o.nz + 1));
          test::check_solid(m, 2);
          CHECK(total_volume(m) == doctest::Approx(0.03 * 0.02 * 0.01).epsilon(1e-12));
        }
  }

  TEST_CASE("deterministic for a seed") {
    BoxOptions o;
    o.nx = o.ny = o.nz = 3;
    o.jitter = 0.2;
    CHECK(generate_box(o).nodes == generate_box(o).nodes);
    BoxOptions p = o;
    p.seed = 2;
    CHECK(generate_box(o).nodes != generate_box(p).nodes);
  }

  TEST_CASE("cell counts whose node or tet count overflows an int are errors, not crashes") {
    // 2001^3 nodes and 6 * 2000^3 tets do not fit int ids (the CLI takes counts up to 1e9).
    BoxOptions o;
    o.nx = o.ny = o.nz = 2000;
    CHECK_THROWS_WITH_AS(generate_box(o), doctest::Contains("too many"), Error);
    o.nx = 1000000000, o.ny = o.nz = 1;
    CHECK_THROWS_WITH_AS(generate_box(o), doctest::Contains("too many"), Error);
  }
}
