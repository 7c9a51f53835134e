#include "mesh/mesher/mesh_shape.hpp"

#include <doctest/doctest.h>

#include <cmath>

#include "generate_checks.hpp"
#include "mesh/quality.hpp"

using namespace softcut;
using namespace softcut::mesh;

namespace {

// A ball of radius r (label 1) around a ball of radius r_in (label 2; 0: none).
LabeledShape balls(double r, double r_in) {
  LabeledShape s;
  s.name = "test balls";
  s.bounds = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-1.2 * r), Eigen::Vector3d::Constant(1.2 * r));
  s.labels = r_in > 0 ? std::vector<int>{1, 2} : std::vector<int>{1};
  s.label = [r, r_in](const Eigen::Vector3d& p) { return p.norm() < r_in ? 2 : p.norm() < r ? 1 : 0; };
  return s;
}

TetMesh with_label(const TetMesh& m, int label) {
  TetMesh out;
  out.nodes = m.nodes;
  std::vector<int> keep;
  for (int t = 0; t < m.num_tets(); ++t)
    if (m.labels(t) == label) keep.push_back(t);
  out.tets.resize(Eigen::Index(keep.size()), 4);
  out.labels = Eigen::VectorXi::Constant(Eigen::Index(keep.size()), label);
  for (size_t i = 0; i < keep.size(); ++i) out.tets.row(Eigen::Index(i)) = m.tets.row(keep[i]);
  // Drop the nodes of other labels so that every node is used.
  std::vector<int> id(size_t(m.num_nodes()), -1);
  int n = 0;
  for (Eigen::Index t = 0; t < out.tets.rows(); ++t)
    for (int v = 0; v < 4; ++v) {
      int& k = id[size_t(out.tets(t, v))];
      if (k < 0) k = n++;
      out.tets(t, v) = k;
    }
  out.nodes.resize(n, 3);
  for (int i = 0; i < m.num_nodes(); ++i)
    if (id[size_t(i)] >= 0) out.nodes.row(id[size_t(i)]) = m.nodes.row(i);
  return out;
}

double ball_volume(double r) { return 4.0 / 3.0 * M_PI * r * r * r; }

}  // namespace

TEST_SUITE("mesh/mesher/mesh_shape") {
  TEST_CASE("a ball: a closed oriented solid inscribed in the sphere with its volume and quality reported") {
    const double r = 0.02;
    MesherOptions o;
    o.cell_size = r / 4;
    MesherReport rep;
    const TetMesh m = mesh_shape(balls(r, 0), o, &rep);
    test::check_solid(m, 2);
    CHECK(rep.tets == m.num_tets());
    CHECK(rep.nodes == m.num_nodes());
    CHECK(rep.min_dihedral_deg == tet_quality(m).min_dihedral_deg);
    CHECK(rep.min_dihedral_deg > 8);
    // Surface vertices lie on the sphere (to the bisection's 1e-6 of the
    // box), so the inscribed polytope is a little smaller than the ball.
    const double v = total_volume(m) / ball_volume(r);
    CHECK(v < 1.0);
    CHECK(v > 0.95);
    double worst = 0;
    for (int i = 0; i < m.num_nodes(); ++i) worst = std::max(worst, m.node(i).norm() - r);
    CHECK(worst < 1e-6);
  }

  TEST_CASE("two labels: each region is a closed solid, so the interface between them is conforming") {
    const double r = 0.02, r_in = 0.009;
    MesherOptions o;
    o.cell_size = r / 5;
    const TetMesh m = mesh_shape(balls(r, r_in), o);
    test::check_solid(m, 2);
    const TetMesh inner = with_label(m, 2), outer = with_label(m, 1);
    test::check_solid(inner, 2);
    test::check_solid(outer, 4);  // a shell: two spheres, Euler 2 + 2
    CHECK(total_volume(inner) / ball_volume(r_in) == doctest::Approx(1).epsilon(0.1));
    CHECK(inner.num_tets() + outer.num_tets() == m.num_tets());
  }

  TEST_CASE("grading: tets near the fine centre are smaller than far from it") {
    const double r = 0.03;
    MesherOptions o;
    o.cell_size = r / 4;
    o.fine_size = o.cell_size / 3;
    o.fine_center = Eigen::Vector3d(0, 0, r);
    o.fine_radius = r / 2;
    const TetMesh m = mesh_shape(balls(r, 0), o);
    test::check_solid(m, 2);
    double near = 0, far = 0;
    int n_near = 0, n_far = 0;
    for (int t = 0; t < m.num_tets(); ++t) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int v = 0; v < 4; ++v) c += m.node(m.tets(t, v)) / 4;
      const double d = (c - o.fine_center).norm(), h = std::cbrt(std::abs(signed_volume(m, t)));
      if (d < o.fine_radius) near += h, ++n_near;
      if (d > 2 * o.fine_radius) far += h, ++n_far;
    }
    REQUIRE(n_near > 0);
    REQUIRE(n_far > 0);
    CHECK(near / n_near < 0.6 * far / n_far);
    CHECK(local_size(o, o.fine_center) == o.fine_size);
    CHECK(local_size(o, Eigen::Vector3d(0, 0, -r)) == o.cell_size);
  }

  TEST_CASE("the estimate before meshing is within 35 % of the tets made") {
    MesherOptions o;
    for (double h : {0.006, 0.004}) {
      o.cell_size = h;
      const LabeledShape s = balls(0.02, 0.008);
      const double est = estimate_tets(s, o);
      const int got = mesh_shape(s, o).num_tets();
      CAPTURE(h);
      CHECK(est / got == doctest::Approx(1).epsilon(0.35));
    }
  }

  TEST_CASE("the same seed gives the same mesh") {
    MesherOptions o;
    o.cell_size = 0.005;
    const TetMesh a = mesh_shape(balls(0.02, 0.008), o), b = mesh_shape(balls(0.02, 0.008), o);
    CHECK(a.nodes == b.nodes);
    CHECK(a.tets == b.tets);
    CHECK(a.labels == b.labels);
  }

  TEST_CASE("bad options and empty shapes are errors naming the shape") {
    const LabeledShape s = balls(0.02, 0);
    MesherOptions o;
    for (double h : {0.0, -1.0, std::nan("")}) {
      o.cell_size = h;
      CHECK_THROWS_WITH_AS(mesh_shape(s, o), doctest::Contains("test balls: cell_size must be a positive number"), Error);
    }
    o.cell_size = 0.005;
    o.fine_radius = 0.01, o.fine_size = 0.01;
    CHECK_THROWS_WITH_AS(mesh_shape(s, o), doctest::Contains("fine_size 0.01 is larger than cell_size"), Error);
    o.fine_radius = 0;
    o.facet_angle_deg = 40;
    CHECK_THROWS_WITH_AS(mesh_shape(s, o), doctest::Contains("facet_angle must be in (0, 30]"), Error);
    o.facet_angle_deg = 25;
    LabeledShape empty = s;
    empty.label = [](const Eigen::Vector3d&) { return 0; };
    CHECK_THROWS_WITH_AS(mesh_shape(empty, o), doctest::Contains("test balls: the mesher made no tetrahedra"), Error);
    LabeledShape flat = s;
    flat.bounds = Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 1, 0));
    CHECK_THROWS_WITH_AS(mesh_shape(flat, o), doctest::Contains("bounding box is empty"), Error);
  }
}
