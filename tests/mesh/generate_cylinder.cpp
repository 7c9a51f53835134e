#include "mesh/generate/cylinder.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "generate_checks.hpp"

using namespace softcut;
using namespace softcut::mesh;

TEST_SUITE("mesh/generate/cylinder") {
  TEST_CASE("closed ball-like surface, positive tets, counts and polygonal volume") {
    for (int rings : {1, 2, 4})
      for (int layers : {4, 12})
        for (double jitter : {0.0, 0.2}) {
          CylinderOptions o;
          o.radius = 0.01, o.length = 0.03;
          o.rings = rings, o.layers = layers, o.jitter = jitter;
          o.base_center = Eigen::Vector3d(0.1, -0.2, 0.3);
          const TetMesh m = generate_cylinder(o);
          CAPTURE(rings);
          CAPTURE(layers);
          CHECK(m.num_nodes() == (1 + 3 * rings * (rings + 1)) * (layers + 1));
          CHECK(m.num_tets() == 18 * rings * rings * layers);
          test::check_solid(m, 2);
          // The section is a regular 6R-gon: area (6R / 2) r^2 sin(2 pi / 6R).
          const double n = 6 * rings;
          const double area = 0.5 * n * o.radius * o.radius * std::sin(2 * std::numbers::pi / n);
          CHECK(total_volume(m) == doctest::Approx(area * o.length).epsilon(1e-12));
          for (int i = 0; i < m.num_nodes(); ++i) {
            const Eigen::Vector3d d = m.node(i) - o.base_center;
            CHECK(std::hypot(d.x(), d.y()) <= o.radius * (1 + 1e-12));
            CHECK(d.z() >= -1e-15);
            CHECK(d.z() <= o.length + 1e-15);
          }
        }
  }

  TEST_CASE("a target tet count picks a resolution within 10 %") {
    for (int target : {500, 2000, 20000}) {
      CylinderOptions o;
      o.target_tets = target;
      const auto r = resolve_cylinder(o);
      const int tets = 18 * r.rings * r.rings * r.layers;
      CAPTURE(target);
      CHECK(std::abs(double(tets) / target - 1) <= 0.1);
      CHECK(generate_cylinder(o).num_tets() == tets);
    }
  }

  TEST_CASE("bad options are errors") {
    CylinderOptions o;
    o.radius = -1;
    CHECK_THROWS_AS(generate_cylinder(o), Error);
    o = {};
    o.rings = 2;
    CHECK_THROWS_AS(generate_cylinder(o), Error);
    o.layers = 2;
    o.jitter = 0.3;
    CHECK_THROWS_AS(generate_cylinder(o), Error);
  }

  TEST_CASE("resolutions whose node or tet count overflows an int are errors, not crashes") {
    CylinderOptions o;
    o.rings = 30000, o.layers = 1;  // 1 + 3 R (R + 1) section points overflow an int
    CHECK_THROWS_WITH_AS(generate_cylinder(o), doctest::Contains("too many"), Error);
    o = {};
    o.radius = 1e-12, o.length = 1;  // the default 4 rings ask for 4e12 layers
    CHECK_THROWS_WITH_AS(generate_cylinder(o), doctest::Contains("too many"), Error);
  }
}
