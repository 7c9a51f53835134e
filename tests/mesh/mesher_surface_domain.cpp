#include "mesh/mesher/surface_domain.hpp"

#include <doctest/doctest.h>

#include <cmath>

#include "core/warning.hpp"
#include "surface_samples.hpp"
#include "test_support.hpp"

using namespace softcut;
using namespace softcut::mesh;
using test::contains;
using test::error_of;

namespace {

SurfaceSoup soup(const test::Soup& s, const std::string& name = "a.off") {
  SurfaceSoup out;
  out.source = name;
  out.points.resize(Eigen::Index(s.points.size()), 3);
  for (std::size_t i = 0; i < s.points.size(); ++i) out.points.row(Eigen::Index(i)) = s.points[i].transpose();
  out.triangles.resize(Eigen::Index(s.tris.size()), 3);
  for (std::size_t t = 0; t < s.tris.size(); ++t) out.triangles.row(Eigen::Index(t)) = s.tris[t].transpose();
  return out;
}

std::string domain_error(const std::vector<SurfaceSoup>& soups) {
  return error_of([&] {
    Diagnostics d;
    surface_domain(soups, 1.0, d);
  });
}

}  // namespace

TEST_SUITE("mesh/mesher/surface_domain") {
  TEST_CASE("a closed surface is label 1, with its volume, scaled to metres") {
    Diagnostics d;
    const SurfaceDomain dom = surface_domain({soup(test::cube(20))}, 1e-3, d);  // a 20 mm cube
    REQUIRE(dom.shells.size() == 1);
    CHECK(dom.shells[0].inside == 1);
    CHECK(dom.shells[0].outside == 0);
    CHECK(dom.volumes.at(1) == doctest::Approx(8e-6));
    CHECK(dom.shape.labels == std::vector<int>{1});
    CHECK(dom.shape.label(Eigen::Vector3d(0.01, 0.01, 0.01)) == 1);
    CHECK(dom.shape.label(Eigen::Vector3d(0.03, 0.01, 0.01)) == 0);
    CHECK(d.warnings.empty());
  }

  TEST_CASE("nested files are labels: the second file's solid inside the first is label 2") {
    Diagnostics d;
    const test::Soup outer = test::sphere(0.04), inner = test::sphere(0.012, Eigen::Vector3d(0.01, 0.005, 0));
    const SurfaceDomain dom = surface_domain({soup(outer, "outer.off"), soup(inner, "inner.off")}, 1.0, d);
    REQUIRE(dom.shells.size() == 2);
    CHECK(dom.shells[1].inside == 2);
    CHECK(dom.shells[1].outside == 1);
    CHECK(dom.shape.label(Eigen::Vector3d(0.01, 0.005, 0)) == 2);
    CHECK(dom.shape.label(Eigen::Vector3d(-0.03, 0, 0)) == 1);
    CHECK(dom.shape.labels == std::vector<int>{1, 2});
    // The volumes of the two labels: the outer solid less the inner, and the inner.
    const auto vol = [](const test::Soup& s) {
      double v = 0;
      for (const auto& t : s.tris) v += s.points[size_t(t[0])].dot(s.points[size_t(t[1])].cross(s.points[size_t(t[2])])) / 6;
      return v;
    };
    CHECK(dom.volumes[1] == doctest::Approx(vol(outer) - vol(inner)));
    CHECK(dom.volumes[2] == doctest::Approx(vol(inner)));
  }

  TEST_CASE("in one file, a piece inside another is a cavity") {
    Diagnostics d;
    const SurfaceDomain dom = surface_domain({soup(test::join({test::cube(4), test::cube(2, Eigen::Vector3d(1, 1, 1))}))}, 1.0, d);
    CHECK(dom.volumes.at(1) == doctest::Approx(64 - 8));
    CHECK(dom.shape.label(Eigen::Vector3d(2, 2, 2)) == 0);
    CHECK(dom.shape.label(Eigen::Vector3d(0.5, 0.5, 0.5)) == 1);
  }

  TEST_CASE("faces turned against their neighbours are turned back, with a coded warning - inward surfaces silently") {
    test::Soup c = test::sphere(1);
    std::swap(c.tris[3][1], c.tris[3][2]);
    std::swap(c.tris[70][1], c.tris[70][2]);
    Diagnostics d;
    const SurfaceDomain dom = surface_domain({soup(c)}, 1.0, d);
    REQUIRE(d.warnings.size() == 1);
    CHECK(warning_code(d.warnings[0]) == "surface_reoriented");
    CHECK(contains(d.warnings[0], "a.off: 2 of 320 triangles faced the other way"));
    CHECK(dom.volumes[1] > 4);
    test::Soup in = test::cube(1);
    for (auto& t : in.tris) std::swap(t[1], t[2]);
    d.warnings.clear();
    CHECK(surface_domain({soup(in)}, 1.0, d).volumes[1] == doctest::Approx(1));
    CHECK(d.warnings.empty());
  }

  TEST_CASE("bad surfaces: not closed, not a manifold, self-intersecting, no volume, empty, each named and located") {
    test::Soup open = test::sphere(1);
    open.tris.erase(open.tris.begin() + 5);
    const std::string e1 = domain_error({soup(open, "liver.stl")});
    CHECK(contains(e1, "liver.stl: the surface is not closed: 3 border edges"));
    CHECK(contains(e1, "e.g. from ("));
    // Two spheres that overlap, in one file and in two.
    const std::string e2 = domain_error({soup(test::join({test::sphere(1), test::sphere(1, Eigen::Vector3d(0.9, 0.1, 0.05))}))});
    CHECK(contains(e2, "a.off (piece "));
    CHECK(contains(e2, "intersect"));
    CHECK(contains(e2, "triangles near ("));
    const std::string e3 = domain_error({soup(test::sphere(1), "organ.stl"), soup(test::sphere(0.5, Eigen::Vector3d(0.8, 0, 0)), "lesion.stl")});
    CHECK((contains(e3, "organ.stl and lesion.stl intersect") || contains(e3, "lesion.stl and organ.stl intersect")));
    // An edge in four triangles: two cubes sharing an edge.
    const std::string e4 = domain_error({soup(test::join({test::cube(1), test::cube(1, Eigen::Vector3d(1, 1, 0))}))});
    CHECK(contains(e4, "edges are shared by more than two triangles"));
    // A closed surface around nothing: a tetrahedron flattened into its base plane.
    test::Soup flat;
    flat.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 0}};
    flat.tris = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
    const std::string e5 = domain_error({soup(flat)});
    CHECK((contains(e5, "encloses no volume") || contains(e5, "intersects itself")));
    test::Soup degenerate;
    degenerate.points = {{0, 0, 0}, {1, 0, 0}};
    degenerate.tris = {{0, 1, 1}};
    CHECK(contains(domain_error({soup(degenerate)}), "no triangle is left"));
    CHECK(contains(domain_error({}), "no surface file"));
    // Pieces touching at one point.
    const std::string e6 = domain_error({soup(test::join({test::cube(1), test::cube(1, Eigen::Vector3d(1, 1, 1))}))});
    CHECK((contains(e6, "not a manifold at") || contains(e6, "intersects itself")));
  }

  TEST_CASE("an inner surface that separates nothing is left out, with a warning") {
    // The first file's piece inside the second file's solid: label 2 on both sides.
    Diagnostics d;
    const SurfaceDomain dom =
        surface_domain({soup(test::cube(1, Eigen::Vector3d(1, 1, 1)), "small.off"), soup(test::cube(3), "big.off")}, 1.0, d);
    CHECK(dom.shells.size() == 1);
    REQUIRE(d.warnings.size() == 1);
    CHECK(contains(d.warnings[0], "small.off: lies inside the solid of a later file"));
    CHECK(dom.shape.labels == std::vector<int>{2});
  }
}
