#include "mesh/quality.hpp"

#include <doctest/doctest.h>

#include <cmath>

#include "mesh/generate/box.hpp"

using namespace softcut;
using namespace softcut::mesh;

namespace {

TetMesh one_tet(const Eigen::Matrix<double, 4, 3>& p) {
  TetMesh m;
  m.nodes = p;
  m.tets.resize(1, 4);
  m.tets << 0, 1, 2, 3;
  m.labels = Eigen::VectorXi::Zero(1);
  return m;
}

const double kRegularDihedral = std::acos(1.0 / 3) * 180 / M_PI;  // 70.53 degrees

}  // namespace

TEST_SUITE("mesh/quality") {
  TEST_CASE("regular tet: aspect 1, all dihedral angles acos(1/3)") {
    Eigen::Matrix<double, 4, 3> p;
    p << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
    p *= 0.01;
    const Eigen::Vector3d a = p.row(0), b = p.row(1), c = p.row(2), d = p.row(3);
    CHECK(aspect_ratio(a, b, c, d) == doctest::Approx(1).epsilon(1e-12));
    for (double x : dihedral_angles_deg(a, b, c, d)) CHECK(x == doctest::Approx(kRegularDihedral).epsilon(1e-12));
    TetMesh m = one_tet(p);
    if (signed_volume(m, 0) < 0) std::swap(m.tets(0, 2), m.tets(0, 3));
    const QualityStats q = tet_quality(m);
    CHECK(q.num_poor == 0);
    CHECK(q.min_volume == doctest::Approx(std::pow(0.02 * std::sqrt(2.0), 3) / (6 * std::sqrt(2.0))));
    CHECK(q.min_edge == doctest::Approx(0.02 * std::sqrt(2.0)));
  }

  TEST_CASE("unit corner tet: known dihedral angles and aspect") {
    const Eigen::Vector3d o(0, 0, 0), x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
    const auto ang = dihedral_angles_deg(o, x, y, z);
    // Edges at the origin: 90 degrees; the others: acos(1 / sqrt 3).
    const double other = std::acos(1 / std::sqrt(3.0)) * 180 / M_PI;
    for (int e = 0; e < 3; ++e) CHECK(ang[size_t(e)] == doctest::Approx(90));
    for (int e = 3; e < 6; ++e) CHECK(ang[size_t(e)] == doctest::Approx(other));
    // R = sqrt(3)/2, r = 1 / (3 + sqrt 3): R / 3r = (3 + sqrt 3) sqrt 3 / 6.
    CHECK(aspect_ratio(o, x, y, z) == doctest::Approx((3 + std::sqrt(3.0)) * std::sqrt(3.0) / 6));
  }

  TEST_CASE("Kuhn tets of a cube: 45, 60 and 90 degrees, aspect (1 + sqrt 2) / sqrt 3") {
    BoxOptions o;
    o.nx = o.ny = o.nz = 1;
    const QualityStats q = tet_quality(generate_box(o));
    CHECK(q.num_tets == 6);
    CHECK(q.min_dihedral_deg == doctest::Approx(45));
    CHECK(q.max_dihedral_deg == doctest::Approx(90));
    CHECK(q.min_aspect == doctest::Approx((1 + std::sqrt(2.0)) / std::sqrt(3.0)));
    CHECK(q.max_aspect == doctest::Approx(q.min_aspect));
    CHECK(q.total_volume == doctest::Approx(1));
    CHECK(q.min_volume == doctest::Approx(1.0 / 6));
    CHECK(q.num_poor == 0);
  }

  TEST_CASE("sliver: four nearly coplanar points of a square are poor on every measure") {
    Eigen::Matrix<double, 4, 3> p;
    const double h = 0.01;  // height of the lifted diagonal pair
    p << 0, 0, 0, 1, 1, 0, 1, 0, h, 0, 1, h;
    TetMesh m = one_tet(p);
    if (signed_volume(m, 0) < 0) std::swap(m.tets(0, 2), m.tets(0, 3));
    const QualityStats q = tet_quality(m);
    CHECK(q.min_dihedral_deg < 2);
    CHECK(q.max_dihedral_deg > 178);
    CHECK(q.max_aspect > 20);
    CHECK(q.num_small_dihedral == 1);
    CHECK(q.num_large_dihedral == 1);
    CHECK(q.num_high_aspect == 1);
    CHECK(q.num_poor == 1);
    CHECK(q.worst_tet == 0);
    // The six angles of any tet: each between 0 and 180, sum between 2 pi and 3 pi.
    const Eigen::Vector3d a = p.row(0), b = p.row(1), c = p.row(2), d = p.row(3);
    double sum = 0;
    for (double x : dihedral_angles_deg(a, b, c, d)) sum += x;
    CHECK(sum > 360);
    CHECK(sum < 540);
  }

  TEST_CASE("degenerate and inverted tets") {
    const Eigen::Vector3d o(0, 0, 0), x(1, 0, 0), y(0, 1, 0);
    CHECK(std::isinf(aspect_ratio(o, x, y, Eigen::Vector3d(0.5, 0.5, 0))));
    Eigen::Matrix<double, 4, 3> p;
    p << 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0;  // negative orientation
    const QualityStats q = tet_quality(one_tet(p));
    CHECK(q.num_nonpositive == 1);
    CHECK(q.min_volume == doctest::Approx(-1.0 / 6));
    CHECK(q.num_poor == 1);
  }

  TEST_CASE("thresholds are honoured") {
    BoxOptions o;
    o.nx = o.ny = o.nz = 1;
    QualityThresholds th;
    th.min_dihedral_deg = 50;  // Kuhn tets have 45-degree angles
    CHECK(tet_quality(generate_box(o), th).num_small_dihedral == 6);
    th = {};
    th.max_aspect = 1.2;
    CHECK(tet_quality(generate_box(o), th).num_high_aspect == 6);
  }
}
