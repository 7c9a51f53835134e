#include "mesh/generate/band.hpp"

#include <doctest/doctest.h>

#include "core/error.hpp"
#include "generate_checks.hpp"

using namespace softcut;
using namespace softcut::mesh;

TEST_SUITE("mesh/generate/band") {
  TEST_CASE("closed, positive, counts, for twists, flares and jitter") {
    for (double twist : {0.0, 90.0, -180.0})
      for (double flare : {1.0, 1.6})
        for (double jitter : {0.0, 0.2}) {
          BandOptions o;
          o.twist_deg = twist, o.flare = flare, o.jitter = jitter;
          o.along = 12, o.across = 4, o.through = 2;
          const TetMesh m = generate_band(o);
          CAPTURE(twist);
          CAPTURE(flare);
          CHECK(m.num_nodes() == 13 * 5 * 3);
          CHECK(m.num_tets() == 6 * 12 * 4 * 2);
          test::check_solid(m, 2);
          if (flare == 1.0 && twist == 0.0 && jitter == 0.0)
            CHECK(total_volume(m) == doctest::Approx(o.length * o.width * o.thickness).epsilon(1e-12));
          // The ends are wider than the middle.
          double end_w = 0, mid_w = 0;
          for (int i = 0; i < m.num_nodes(); ++i) {
            const Eigen::Vector3d p = m.node(i);
            if (p.z() < 1e-9) end_w = std::max(end_w, p.head<2>().norm());
            if (std::abs(p.z() - 0.5 * o.length) < 1e-9) mid_w = std::max(mid_w, p.head<2>().norm());
          }
          if (flare > 1) CHECK(end_w > 1.3 * mid_w);
        }
  }

  TEST_CASE("twist turns the end sections by the requested angle") {
    BandOptions o;
    o.along = 8, o.across = 2, o.through = 1, o.twist_deg = 90, o.flare = 1;
    const TetMesh m = generate_band(o);
    // Node (iw = across, it = 0) of the first and last layer: the long axis of the section.
    const int np = (o.across + 1) * (o.through + 1);
    const Eigen::Vector3d a = m.node(o.across) - m.node(0), b = m.node(o.across + np * o.along) - m.node(np * o.along);
    CHECK(a.head<2>().normalized().dot(b.head<2>().normalized()) == doctest::Approx(0).epsilon(1e-9));
  }

  TEST_CASE("targets pick a resolution within 10 %, same options, same mesh") {
    for (int target : {300, 5000}) {
      BandOptions o;
      o.target_tets = target;
      o.jitter = 0.1;
      const TetMesh m = generate_band(o);
      CHECK(std::abs(double(m.num_tets()) / target - 1) <= 0.1);
      test::check_solid(m, 2);
      CHECK(generate_band(o).nodes == m.nodes);
    }
  }

  TEST_CASE("bad options are errors") {
    BandOptions o;
    o.flare = 0.5;
    CHECK_THROWS_AS(generate_band(o), Error);
    o = {};
    o.along = 3;
    CHECK_THROWS_AS(generate_band(o), Error);
  }

  TEST_CASE("resolutions whose node or tet count overflows an int are errors, not crashes") {
    BandOptions o;
    o.along = 1, o.across = 100000, o.through = 100000;
    CHECK_THROWS_WITH_AS(generate_band(o), doctest::Contains("too many"), Error);
    o = {};
    o.thickness = 1e-12;  // default cells of half the thickness: 2e10 across
    CHECK_THROWS_WITH_AS(generate_band(o), doctest::Contains("too many"), Error);
  }
}
