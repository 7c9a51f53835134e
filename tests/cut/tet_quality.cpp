#include "cut/tet_quality.hpp"

#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>

using namespace softcut;
using Eigen::Vector3d;

namespace {

// Independent dihedral angle at edge (p, q) between the faces through r and s:
// the angle between r and s projected onto the plane normal to the edge.
double dihedral_at(const Vector3d& p, const Vector3d& q, const Vector3d& r, const Vector3d& s) {
  const Vector3d e = (q - p).normalized();
  Vector3d u = r - p, v = s - p;
  u -= u.dot(e) * e;
  v -= v.dot(e) * e;
  return std::acos(std::clamp(u.normalized().dot(v.normalized()), -1.0, 1.0)) * 180 / std::numbers::pi;
}

double brute_min_dihedral(const Vector3d x[4]) {
  double m = 180;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      int o[2], n = 0;
      for (int k = 0; k < 4; ++k)
        if (k != i && k != j) o[n++] = k;
      m = std::min(m, dihedral_at(x[i], x[j], x[o[0]], x[o[1]]));
    }
  return m;
}

}  // namespace

TEST_SUITE("cut/tet_quality") {
  TEST_CASE("known shapes: regular tet and Kuhn cube corner and flat tet") {
    const Vector3d a(1, 1, 1), b(1, -1, -1), c(-1, 1, -1), d(-1, -1, 1);
    CHECK(cut::min_dihedral_deg(a, b, c, d) == doctest::Approx(std::acos(1.0 / 3) * 180 / std::numbers::pi));
    CHECK(std::abs(cut::volume_length_ratio(a, b, c, d)) == doctest::Approx(1.0));
    const Vector3d k0(0, 0, 0), k1(1, 0, 0), k2(1, 1, 0), k3(1, 1, 1);
    CHECK(cut::min_dihedral_deg(k0, k1, k2, k3) == doctest::Approx(45.0));
    CHECK(cut::min_dihedral_deg(k0, k1, k2, Vector3d(0.5, 0.5, 0)) == 0.0);
  }

  TEST_CASE("minimum dihedral angle matches an edge-projection computation on random tets") {
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int trial = 0; trial < 500; ++trial) {
      Vector3d x[4];
      for (auto& p : x) p = Vector3d(u(rng), u(rng), u(rng));
      const double q = cut::min_dihedral_deg(x[0], x[1], x[2], x[3]);
      CHECK(q == doctest::Approx(brute_min_dihedral(x)).epsilon(1e-9));
      // Invariant under vertex order, scaling and rotation.
      const Eigen::Matrix3d r = Eigen::AngleAxisd(u(rng) * 3, Vector3d(u(rng), u(rng), 1).normalized()).toRotationMatrix();
      CHECK(cut::min_dihedral_deg(3 * r * x[2], 3 * r * x[0], 3 * r * x[1], 3 * r * x[3]) ==
            doctest::Approx(q).epsilon(1e-9));
      // Volume-length ratio flips sign with orientation, lies in [-1, 1].
      const double v = cut::volume_length_ratio(x[0], x[1], x[2], x[3]);
      CHECK(cut::volume_length_ratio(x[1], x[0], x[2], x[3]) == doctest::Approx(-v));
      CHECK(std::abs(v) <= 1 + 1e-12);
    }
  }
}
