#include "render/tool_geometry.hpp"

#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <map>
#include <numbers>

#include "core/error.hpp"

using namespace softcut;
using render::Triangles;

namespace {

// Enclosed volume by the divergence theorem (positive for outward winding).
double volume(const Triangles& t) {
  double v = 0;
  for (int i = 0; i < t.count(); ++i) {
    const Eigen::Vector3d a = t.positions[size_t(3 * i)].cast<double>(), b = t.positions[size_t(3 * i + 1)].cast<double>(),
                          c = t.positions[size_t(3 * i + 2)].cast<double>();
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

// Every directed edge must be matched by its reverse: a closed, consistently
// oriented surface. Vertices are matched on a 1e-7 m grid.
int unmatched_edges(const Triangles& t) {
  auto key = [](const Eigen::Vector3f& p) {
    return std::array<long, 3>{std::lround(p.x() * 1e7), std::lround(p.y() * 1e7), std::lround(p.z() * 1e7)};
  };
  std::map<std::pair<std::array<long, 3>, std::array<long, 3>>, int> count;
  for (int i = 0; i < t.count(); ++i)
    for (int k = 0; k < 3; ++k) {
      const auto a = key(t.positions[size_t(3 * i + k)]), b = key(t.positions[size_t(3 * i + (k + 1) % 3)]);
      if (a == b) continue;
      ++count[{a, b}];
      --count[{b, a}];
    }
  int bad = 0;
  for (const auto& [e, n] : count) bad += n != 0;
  return bad;
}

constexpr double kPi = std::numbers::pi;

}  // namespace

TEST_SUITE("render/tool_geometry") {
  TEST_CASE("probe is a closed outward sphere and shaft of the right size") {
    for (int S : {6, 12, 24, 40}) {
      Triangles t;
      render::ProbeShape p{{0.1, 0.2, 0.3}, {1, 1, 0}, 0.01, 0.05};
      const int n = render::add_tool(t, p, S, {1, 1, 1, 1});
      CAPTURE(S);
      CHECK(n == 2 * S * (S / 2 - 1) + 4 * S);
      CHECK(n == render::sphere_triangles(S) + render::cylinder_triangles(S));
      CHECK(t.count() == n);
      // The sphere's corners lie on it, its normals point away from its centre.
      for (int i = 0; i < 3 * render::sphere_triangles(S); ++i) {
        const Eigen::Vector3d d = t.positions[size_t(i)].cast<double>() - p.tip;
        CHECK(d.norm() == doctest::Approx(0.01).epsilon(1e-5));
        CHECK(t.normals[size_t(i)].cast<double>().dot(d.normalized()) == doctest::Approx(1.0).epsilon(1e-5));
      }
      // Sphere and cylinder are separately closed; volumes add up (the shaft
      // sits inside the ball for a bit; both are counted).
      CHECK(unmatched_edges(t) == 0);
      const double ball = 4.0 / 3.0 * kPi * 1e-6, shaft = kPi * 0.005 * 0.005 * 0.05;
      const double polygon = S / (2.0 * kPi) * std::sin(2.0 * kPi / S);  // inscribed polygon / circle area
      const double v = volume(t);
      CHECK(v > 0);
      CHECK(v < ball + shaft * polygon * 1.0001);
      CHECK(v > (S >= 24 ? 0.95 : 0.5) * ball + shaft * polygon * 0.9999);
    }
  }

  TEST_CASE("grasper is two tapered jaws, a clevis and a shaft, the jaws opened by the angle") {
    Triangles t;
    render::GrasperShape g;
    g.opening_deg = 40;
    const int S = 12;
    CHECK(render::add_tool(t, g, S, {1, 1, 1, 1}, {0, 0, 0, 1}) == 2 * 12 + 4 * S + 4 * S);
    CHECK(unmatched_edges(t) == 0);
    // Jaws: length x mean width x thickness; clevis and shaft: polygonal cylinders.
    const double jaw = g.jaw_length * 0.75 * g.jaw_width * g.jaw_width / 3.0;
    const double disc = S / 2.0 * std::sin(2.0 * kPi / S) * 0.25 * g.jaw_width * g.jaw_width;
    CHECK(volume(t) == doctest::Approx(2 * jaw + disc * g.jaw_width + disc * g.shaft_length).epsilon(1e-4));
    // The jaws (steel) and the shaft (dark): the shaft's triangles come last.
    CHECK(t.colors.front() == render::Rgba(1, 1, 1, 1));
    CHECK(t.colors.back() == render::Rgba(0, 0, 0, 1));
    // The two jaw tips are apart by about 2 L sin(opening / 2) across the hinge plane.
    double lo = 1e9, hi = -1e9;
    const Eigen::Vector3d across = g.hinge.cross(g.axis).normalized();
    for (int i = 0; i < 3 * 24; ++i) {
      const double s = t.positions[size_t(i)].cast<double>().dot(across);
      lo = std::min(lo, s), hi = std::max(hi, s);
    }
    const double spread = 2 * g.jaw_length * std::sin(20 * kPi / 180);
    CHECK(hi - lo > spread);
    CHECK(hi - lo < spread + 2 * g.jaw_width);
    // Closed jaws meet along the axis without overlapping.
    Triangles closed;
    g.opening_deg = 0;
    render::add_tool(closed, g, S, {1, 1, 1, 1});
    lo = 1e9, hi = -1e9;
    for (int i = 0; i < 3 * 12; ++i) {
      const double s = closed.positions[size_t(i)].cast<double>().dot(across);
      lo = std::min(lo, s), hi = std::max(hi, s);
    }
    CHECK(std::min(std::abs(lo), std::abs(hi)) < 1e-9);  // the first jaw ends on the axis plane
  }

  TEST_CASE("scalpel is a thin blade, sharp along its edge, and a flat handle") {
    Triangles t;
    render::ScalpelShape s;
    const int S = 8;
    CHECK(render::add_tool(t, s, S, {1, 1, 1, 1}, {0, 0, 0, 1}) == 4 + 12);
    CHECK(unmatched_edges(t) == 0);
    const Eigen::Vector3d n = (s.edge_b - s.edge_a).cross(s.spine - s.edge_a).normalized();
    const double th = 0.5 * s.handle_radius;
    const double blade = std::abs((s.edge_b - s.edge_a).dot((s.spine - s.edge_a).cross(th * n))) / 6.0;
    const double handle = (s.handle_end - s.spine).norm() * 3 * s.handle_radius * 1.2 * s.handle_radius;
    CHECK(volume(t) == doctest::Approx(blade + handle).epsilon(1e-6));
    // The cutting edge is a line of the blade (zero thickness there).
    int on_edge = 0;
    for (int i = 0; i < 3 * 4; ++i)
      on_edge += (t.positions[size_t(i)].cast<double>() - s.edge_a).norm() < 1e-7 ||
                 (t.positions[size_t(i)].cast<double>() - s.edge_b).norm() < 1e-7;
    CHECK(on_edge == 6);
  }

  TEST_CASE("degenerate tools are refused") {
    Triangles t;
    render::ScalpelShape s;
    s.spine = 0.5 * (s.edge_a + s.edge_b);
    CHECK_THROWS_WITH_AS(render::add_tool(t, s, 8, {}), doctest::Contains("collinear"), Error);
    render::GrasperShape g;
    g.hinge = g.axis;
    CHECK_THROWS_WITH_AS(render::add_tool(t, g, 8, {}), doctest::Contains("grasper hinge"), Error);
    CHECK_THROWS_WITH_AS(render::add_tool(t, render::ProbeShape{}, 7, {}), doctest::Contains("even and >= 6"),
                         Error);
  }
}
