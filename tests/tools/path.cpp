#include "tools/path.hpp"

#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>

#include "core/error.hpp"

using softcut::tools::Path;
using softcut::tools::evaluate;
using V = Eigen::Vector3d;

TEST_SUITE("tools/path") {
  TEST_CASE("polyline: keys at their times, constant speed per segment, held outside") {
    const Path p = Path::polyline({0.0, 1.0, 3.0}, {V(0, 0, 0), V(1, 0, 0), V(1, 2, 0)});
    CHECK((evaluate(p, -1.0) - V(0, 0, 0)).norm() == 0);
    CHECK((evaluate(p, 1.0) - V(1, 0, 0)).norm() < 1e-15);
    CHECK((evaluate(p, 3.0) - V(1, 2, 0)).norm() == 0);
    CHECK((evaluate(p, 5.0) - V(1, 2, 0)).norm() == 0);
    CHECK((evaluate(p, 0.25) - V(0.25, 0, 0)).norm() < 1e-15);
    CHECK((evaluate(p, 2.0) - V(1, 1, 0)).norm() < 1e-15);
    CHECK((evaluate(p, 2.5) - V(1, 1.5, 0)).norm() < 1e-15);
  }

  TEST_CASE("catmull_rom passes through every key and is C1 at interior keys") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<double> times{0.0};
    std::vector<V> pts{V(u(rng), u(rng), u(rng))};
    for (int k = 1; k < 6; ++k) {
      times.push_back(times.back() + 0.2 + 0.5 * (u(rng) + 1));
      pts.push_back(V(u(rng), u(rng), u(rng)));
    }
    const Path p = Path::catmull_rom(times, pts);
    for (size_t k = 0; k < times.size(); ++k) CHECK((evaluate(p, times[k]) - pts[k]).norm() < 1e-14);
    const double h = 1e-6;
    for (size_t k = 1; k + 1 < times.size(); ++k) {
      const V left = (evaluate(p, times[k]) - evaluate(p, times[k] - h)) / h;
      const V right = (evaluate(p, times[k] + h) - evaluate(p, times[k])) / h;
      const V expected = (pts[k + 1] - pts[k - 1]) / (times[k + 1] - times[k - 1]);
      CHECK((left - expected).norm() < 1e-4 * (1 + expected.norm()));
      CHECK((right - expected).norm() < 1e-4 * (1 + expected.norm()));
    }
  }

  TEST_CASE("catmull_rom through collinear evenly timed keys is the straight line") {
    const Path p = Path::catmull_rom({0, 1, 2, 3}, {V(0, 0, 0), V(1, 1, 0), V(2, 2, 0), V(3, 3, 0)});
    for (double t = 0; t <= 3; t += 0.125) CHECK((evaluate(p, t) - V(t, t, 0)).norm() < 1e-14);
  }

  TEST_CASE("arc: constant radius, angle linear in time, plane perpendicular to the axis") {
    const V c(0.1, -0.2, 0.3), axis(0, 0, 2), start(0.1 + 0.05, -0.2, 0.3);
    const Path p = Path::arc(c, axis, start, std::numbers::pi, 1.0, 3.0);
    for (double t = 0.0; t <= 4.0; t += 0.1) {
      const V x = evaluate(p, t);
      CHECK((x - c).norm() == doctest::Approx(0.05).epsilon(1e-13));
      CHECK(std::abs((x - c).z()) < 1e-15);
    }
    CHECK((evaluate(p, 0.0) - start).norm() < 1e-15);
    CHECK((evaluate(p, 2.0) - V(0.1, -0.2 + 0.05, 0.3)).norm() < 1e-15);  // quarter turn, counter-clockwise about +z
    CHECK((evaluate(p, 3.0) - V(0.05, -0.2, 0.3)).norm() < 1e-15);
    CHECK((evaluate(p, 9.0) - evaluate(p, 3.0)).norm() == 0);
  }

  TEST_CASE("bad paths are refused with the item named") {
    using softcut::Error;
    CHECK_THROWS_WITH_AS(check_path(Path::polyline({0.0, 0.0}, {V::Zero(), V::Ones()}), "tool 'probe' path"),
                         doctest::Contains("tool 'probe' path"), Error);
    CHECK_THROWS_AS(check_path(Path::polyline({0.0}, {V::Zero(), V::Ones()}), "x"), Error);
    CHECK_THROWS_AS(check_path(Path::catmull_rom({}, {}), "x"), Error);
    CHECK_THROWS_AS(check_path(Path::arc(V::Zero(), V::Zero(), V::UnitX(), 1, 0, 1), "x"), Error);
    CHECK_THROWS_AS(check_path(Path::arc(V::Zero(), V::UnitZ(), V::UnitX(), 1, 1, 1), "x"), Error);
    CHECK_THROWS_AS(check_path(Path::fixed_at(V(NAN, 0, 0)), "x"), Error);
    CHECK(softcut::tools::path_kind_from_string("arc", "x") == Path::Kind::arc);
    CHECK_THROWS_AS(softcut::tools::path_kind_from_string("bezier", "x"), Error);
  }
}
