#include "cut/rest_map.hpp"

#include <doctest/doctest.h>

#include <Eigen/LU>
#include <random>

#include "core/error.hpp"
#include "mesh/generate/box.hpp"

using namespace softcut;
using Eigen::Vector3d;

namespace {

// x -> a x + b with a = I + entries in [-0.2, 0.2], b in [-0.2, 0.2]^3; returns
// the displacement it gives every node of m.
Eigen::MatrixX3d random_affine(const mesh::TetMesh& m, std::mt19937& rng, Eigen::Matrix3d& a, Vector3d& b) {
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  a = Eigen::Matrix3d::Identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a(i, j) += u(rng);
  b = Vector3d(u(rng), u(rng), u(rng));
  Eigen::MatrixX3d disp(m.num_nodes(), 3);
  for (int v = 0; v < m.num_nodes(); ++v) disp.row(v) = (a * m.node(v) + b - m.node(v)).transpose();
  return disp;
}

}  // namespace

TEST_SUITE("cut/rest_map") {
  TEST_CASE("an affine deformation is inverted exactly inside and outside the body") {
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> p(-0.3, 1.3);
    mesh::BoxOptions box;
    box.nx = box.ny = box.nz = 3;
    box.jitter = 0.1;
    const mesh::TetMesh m = mesh::generate_box(box);
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::Matrix3d a;
      Vector3d b;
      const Eigen::MatrixX3d disp = random_affine(m, rng, a, b);
      for (int k = 0; k < 20; ++k) {
        const Vector3d rest(p(rng), p(rng), p(rng));
        const Vector3d x = a * rest + b;
        CHECK((cut::deformed_to_rest(m, disp, x) - rest).norm() <= 1e-10);
      }
    }
  }

  TEST_CASE("deformed_tet_at finds the deformed tet around a point, and none outside the body") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> p(-0.3, 1.3);
    mesh::BoxOptions box;  // the unit cube
    box.nx = box.ny = box.nz = 3;
    box.jitter = 0.1;
    const mesh::TetMesh m = mesh::generate_box(box);
    Eigen::Matrix3d a;
    Vector3d b;
    const Eigen::MatrixX3d disp = random_affine(m, rng, a, b);
    int inside = 0;
    for (int k = 0; k < 200; ++k) {
      const Vector3d rest(p(rng), p(rng), p(rng));
      const bool in = (rest.array() > 1e-9).all() && (rest.array() < 1 - 1e-9).all();
      const int t = cut::deformed_tet_at(m, disp, a * rest + b);
      INFO("rest point ", rest.transpose());
      CHECK((t >= 0) == in);
      if (t < 0) continue;
      ++inside;
      // The rest tet of that index contains the rest point.
      Eigen::Matrix3d e;
      e << m.node(m.tets(t, 1)) - m.node(m.tets(t, 0)), m.node(m.tets(t, 2)) - m.node(m.tets(t, 0)),
          m.node(m.tets(t, 3)) - m.node(m.tets(t, 0));
      const Vector3d l = e.lu().solve(rest - m.node(m.tets(t, 0)));
      CHECK(l.minCoeff() >= -1e-9);
      CHECK(l.sum() <= 1 + 1e-9);
    }
    CHECK(inside > 50);
    // A mask that leaves out the tet around the point finds none.
    const Vector3d x = a * Vector3d(0.5, 0.5, 0.5) + b;
    const int t = cut::deformed_tet_at(m, disp, x);
    REQUIRE(t >= 0);
    std::vector<char> mask(size_t(m.num_tets()), 1);
    mask[size_t(t)] = 0;
    const int other = cut::deformed_tet_at(m, disp, x, mask);
    CHECK(other != t);
    CHECK_THROWS_AS(cut::deformed_tet_at(m, disp.topRows(3), x), Error);
  }

  TEST_CASE("a swept surface maps vertex by vertex and bad input is refused") {
    mesh::BoxOptions box;
    const mesh::TetMesh m = mesh::generate_box(box);
    Eigen::MatrixX3d disp = Eigen::MatrixX3d::Zero(m.num_nodes(), 3);
    disp.col(0).setConstant(0.25);  // rigid shift by +0.25 in x
    const auto s = cut::sweep_triangle(Vector3d(0.5, 0, 0), Vector3d(0.75, 1, 0), Vector3d(0.5, 0, 1));
    const auto r = cut::deformed_to_rest(m, disp, s);
    CHECK((r.triangles[0].row(0).array() - s.triangles[0].row(0).array() + 0.25).abs().maxCoeff() <= 1e-12);
    CHECK_THROWS_AS(cut::deformed_to_rest(m, Eigen::MatrixX3d::Zero(3, 3), Vector3d(0, 0, 0)), Error);
    CHECK_THROWS_AS(cut::deformed_to_rest(m, disp, Vector3d(0, 0, 0), std::vector<char>(size_t(m.num_tets()), 0)),
                    Error);
  }
}
