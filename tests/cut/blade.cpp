#include "cut/blade.hpp"

#include <doctest/doctest.h>

#include <random>

using namespace softcut;
using Eigen::Vector3d;

namespace {

Vector3d rand_point(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  return Vector3d(u(rng), u(rng), u(rng));
}

}  // namespace

TEST_SUITE("cut/blade") {
  TEST_CASE("a blade segment sweeps two triangles and a blade at rest sweeps nothing") {
    const Vector3d a(0, 0, 0), b(1, 0, 0), a1(0, 0, -1), b1(1, 0, -1);
    const auto s = cut::sweep_segment(a, b, a1, b1);
    CHECK(s.triangles.size() == 2);
    CHECK(cut::sweep_segment(a, b, a, b).triangles.empty());
    CHECK(cut::sweep_segment(a, a, a1, a1).triangles.empty());
    // Sliding along its own length: degenerate (collinear) sweep.
    CHECK(cut::sweep_segment(a, b, a + Vector3d(0.5, 0, 0), b + Vector3d(0.5, 0, 0)).triangles.empty());
    CHECK(cut::sweep_triangle(a, b, a1).triangles.size() == 1);
  }

  TEST_CASE("segment crossings agree with a dense sampling of the segment") {
    std::mt19937 rng(1);
    int hits = 0;
    for (int trial = 0; trial < 300; ++trial) {
      const auto s = cut::sweep_triangle(rand_point(rng), rand_point(rng), rand_point(rng));
      const Vector3d a = rand_point(rng), b = rand_point(rng);
      const double t = cut::segment_crossing(s, a, b);
      // Independent truth: the sampled distance profile along a-b reaches
      // (near) zero exactly when the segment meets the triangle.
      double dmin = 1e9, tmin = 0;
      for (int k = 0; k <= 4000; ++k) {
        const double tk = k / 4000.0, d = cut::point_triangle_distance(a + tk * (b - a), s.triangles[0]);
        if (d < dmin) dmin = d, tmin = tk;
      }
      const double step = (b - a).norm() / 4000;
      if (t >= 0) {
        ++hits;
        CHECK(cut::point_triangle_distance(a + t * (b - a), s.triangles[0]) <= 1e-9);
        CHECK(std::abs(t - tmin) <= 2.0 / 4000 + 1e-9);
        CHECK(dmin <= step);
      } else {
        CHECK(dmin > 1e-9);  // no sample touches the triangle
      }
    }
    CHECK(hits > 15);  // the random set exercises both outcomes
    CHECK(hits < 270);
  }

  TEST_CASE("point-triangle distance matches a brute-force minimum over the triangle") {
    std::mt19937 rng(2);
    for (int trial = 0; trial < 200; ++trial) {
      Eigen::Matrix3d tri;
      for (int k = 0; k < 3; ++k) tri.col(k) = rand_point(rng);
      const Vector3d x = 2 * rand_point(rng);
      double brute = 1e9;
      const int n = 300;
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
          const Vector3d p = tri.col(0) + (tri.col(1) - tri.col(0)) * (double(i) / n) + (tri.col(2) - tri.col(0)) * (double(j) / n);
          brute = std::min(brute, (x - p).norm());
        }
      const double d = cut::point_triangle_distance(x, tri);
      CHECK(d <= brute + 1e-12);
      CHECK(d >= brute - 0.02);  // sampling resolution of the brute force
    }
  }

  TEST_CASE("a segment lying in the blade plane does not count as crossing it") {
    const auto s = cut::sweep_triangle(Vector3d(0, 0, 0), Vector3d(2, 0, 0), Vector3d(0, 2, 0));
    CHECK(cut::segment_crossing(s, Vector3d(0.1, 0.1, 0), Vector3d(0.5, 0.5, 0)) < 0);
    CHECK(cut::segment_crossing(s, Vector3d(0.1, 0.1, -1), Vector3d(0.1, 0.1, 1)) == doctest::Approx(0.5));
    // Touching at an end point: t = 0 (the cutter snaps it to that node).
    CHECK(cut::segment_crossing(s, Vector3d(0.1, 0.1, 0), Vector3d(0.1, 0.1, 1)) == doctest::Approx(0));
    // Past the blade's edge: no crossing.
    CHECK(cut::segment_crossing(s, Vector3d(1.5, 1.5, -1), Vector3d(1.5, 1.5, 1)) < 0);
  }
}
