#include "render/primitives.hpp"

#include <doctest/doctest.h>

#include <Eigen/Geometry>

TEST_SUITE("render/primitives") {
  TEST_CASE("a flat triangle carries its right-hand normal and one colour") {
    softcut::render::Triangles t;
    const softcut::render::Rgba c(0.1f, 0.2f, 0.3f, 1.0f);
    t.add_flat({0, 0, 0}, {0, 2, 0}, {0, 0, 3}, c);  // normal (2 e_y) x (3 e_z) = +x
    t.add_flat({0, 0, 0}, {0, 0, 3}, {0, 2, 0}, c);
    REQUIRE(t.count() == 2);
    for (int k = 0; k < 3; ++k) {
      CHECK(t.normals[size_t(k)] == Eigen::Vector3f(1, 0, 0));
      CHECK(t.normals[size_t(3 + k)] == Eigen::Vector3f(-1, 0, 0));
      CHECK(t.colors[size_t(k)] == c);
    }
    t.add_flat({0, 0, 0}, {1, 1, 1}, {2, 2, 2}, c);  // degenerate: some unit normal, never NaN
    CHECK(t.normals.back().allFinite());
    CHECK(t.normals.back().norm() == doctest::Approx(1.0));
  }

  TEST_CASE("points and lines keep their vertices in order") {
    softcut::render::Primitives p;
    p.add({1, 2, 3}, {1, 0, 0, 1});
    p.add({4, 5, 6}, {0, 1, 0, 1});
    REQUIRE(p.vertices() == 2);
    CHECK(p.positions[1] == Eigen::Vector3f(4, 5, 6));
    CHECK(p.colors[0] == softcut::render::Rgba(1, 0, 0, 1));
  }
}
