#include "cut/cutter.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "core/error.hpp"
#include "cut/tet_quality.hpp"
#include "mesh/generate/box.hpp"
#include "mesh/surface.hpp"
#include "mesh_checks.hpp"

using namespace softcut;
using Eigen::Vector3d;

namespace {

// Runs blade steps on a unit box and checks every invariant after each.
struct Runner {
  mesh::TetMesh m;
  cut::CutState st;
  cut::CutOptions opt;
  mesh::TetMesh start;
  std::vector<char> locked0, cuttable0;
  double volume0 = 0, worst0 = 180;
  bool expect_twins = true;  // false once a blade may pass separated sides again
  std::vector<cut::CutRecord> records;

  explicit Runner(const mesh::BoxOptions& box, std::vector<char> cuttable = {}) {
    m = mesh::generate_box(box);
    if (cuttable.empty()) cuttable.assign(size_t(m.num_tets()), 1);
    st = cut::make_cut_state(m, cuttable, std::vector<char>(size_t(m.num_nodes()), 0));
    start = m;
    locked0 = st.locked;
    cuttable0 = st.cuttable;
    volume0 = mesh::total_volume(m);
    for (int t = 0; t < m.num_tets(); ++t) worst0 = std::min(worst0, cut::min_dihedral_deg(m, t));
  }

  const cut::CutRecord& step(const cut::SweptSurface& blade) {
    const mesh::TetMesh before = m;
    const std::vector<char> locked = st.locked;
    records.push_back(cut::cut_step(m, st, blade, opt));
    const cut::CutRecord& r = records.back();
    const auto c = test::check_mesh(m, Vector3d::Zero(), Vector3d::Ones());
    CHECK(c.faces_over_two == 0);
    CHECK(c.open_edges == 0);
    if (expect_twins) {
      CHECK(c.unmatched_boundary == 0);
      CHECK(c.hanging_nodes == 0);
    }
    CHECK(c.inverted == 0);
    CHECK(c.worst_dihedral >= std::min(opt.min_dihedral_deg, worst0) - 1e-9);
    CHECK(std::abs(c.volume - volume0) <= 1e-12 * volume0);
    double worst_region = 180;
    for (int t = 0; t < m.num_tets(); ++t)
      if (st.cuttable[size_t(t)]) worst_region = std::min(worst_region, cut::min_dihedral_deg(m, t));
    CHECK(r.worst_dihedral_deg == doctest::Approx(worst_region));
    // Existing nodes never move; non-cuttable tets never change.
    CHECK(m.nodes.topRows(before.num_nodes()) == before.nodes);
    for (int t = 0; t < start.num_tets(); ++t)
      if (!cuttable0[size_t(t)]) CHECK(m.tets.row(t) == start.tets.row(t));
    // The record maps any nodal field; positions are one (split points lie on
    // their edges, copies on their originals).
    REQUIRE(int(r.tet_parent.size()) == m.num_tets());
    REQUIRE(r.nodes_before + int(r.new_nodes.size()) == m.num_nodes());
    const Eigen::MatrixX3d mapped = cut::map_node_field(r, before.nodes);
    CHECK((mapped - m.nodes).cwiseAbs().maxCoeff() <= 1e-14);
    for (const auto& nn : r.new_nodes) {
      CHECK(nn.parent[0] < r.nodes_before);
      CHECK(nn.parent[1] < r.nodes_before);
      // Locked nodes are never copied, edges between two locked nodes never split.
      if (nn.duplicate && nn.parent[1] < 0) CHECK(!locked[size_t(nn.parent[0])]);
      if (!nn.duplicate) CHECK(!(locked[size_t(nn.parent[0])] && locked[size_t(nn.parent[1])]));
    }
    for (int t = 0; t < m.num_tets(); ++t) CHECK(m.labels(t) == before.labels(r.tet_parent[size_t(t)]));
    // Conformity of the bisection itself: no tet keeps an edge that was split.
    std::vector<std::array<int, 2>> split_edges;
    for (const auto& nn : r.new_nodes)
      if (!nn.duplicate) split_edges.push_back({std::min(nn.parent[0], nn.parent[1]), std::max(nn.parent[0], nn.parent[1])});
    std::sort(split_edges.begin(), split_edges.end());
    int unsplit = 0;
    for (int t = 0; t < m.num_tets(); ++t)
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) {
          const std::array<int, 2> e = {std::min(m.tets(t, i), m.tets(t, j)), std::max(m.tets(t, i), m.tets(t, j))};
          unsplit += std::binary_search(split_edges.begin(), split_edges.end(), e);
        }
    CHECK(unsplit == 0);
    // Tets the record does not list as changed are unchanged.
    std::vector<char> changed(size_t(m.num_tets()), 0);
    for (int t : r.changed_tets) changed[size_t(t)] = 1;
    for (int t = 0; t < before.num_tets(); ++t)
      if (!changed[size_t(t)]) CHECK(m.tets.row(t) == before.tets.row(t));
    return r;
  }
};

// Blade spanning the whole box in a plane through `c` with normal `n`,
// lowered from above the box to below it in `steps` steps.
std::vector<cut::SweptSurface> through_cut(const Vector3d& c, const Vector3d& n, int steps, double from = 2.5,
                                           double to = -2.5) {
  const Vector3d nn = n.normalized();
  Vector3d b = nn.cross(Vector3d::UnitZ());
  if (b.norm() < 1e-6) b = nn.cross(Vector3d::UnitX());
  b.normalize();
  const Vector3d d = nn.cross(b).normalized() * (nn.cross(b).normalized().z() < 0 ? -1 : 1);  // upward
  std::vector<cut::SweptSurface> out;
  for (int k = 0; k < steps; ++k) {
    const double h0 = from + (to - from) * k / steps, h1 = from + (to - from) * (k + 1) / steps;
    out.push_back(cut::sweep_segment(c + h0 * d - 2.5 * b, c + h0 * d + 2.5 * b, c + h1 * d - 2.5 * b,
                                     c + h1 * d + 2.5 * b));
  }
  return out;
}

mesh::BoxOptions random_box(std::mt19937& rng, int max_cells = 4) {
  std::uniform_int_distribution<int> cells(2, max_cells);
  std::uniform_real_distribution<double> jit(0.0, 0.2);
  mesh::BoxOptions b;
  b.nx = cells(rng), b.ny = cells(rng), b.nz = cells(rng);
  b.jitter = jit(rng);
  b.seed = rng();
  return b;
}

Vector3d random_plane_normal(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  return Vector3d(1, u(rng), 0.5 * u(rng)).normalized();
}

// Every node of component `comp` lies on the expected side of the plane, up to `tol`.
void check_sides(const mesh::TetMesh& m, const std::vector<int>& comp, const Vector3d& c, const Vector3d& n,
                 double tol) {
  double side[2] = {0, 0};  // summed signed distance per component picks its side
  for (int t = 0; t < m.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) side[comp[size_t(t)]] += n.dot(m.node(m.tets(t, k)) - c);
  CHECK(side[0] * side[1] < 0);
  double worst = 0;
  for (int t = 0; t < m.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) {
      const double d = n.dot(m.node(m.tets(t, k)) - c) * (side[comp[size_t(t)]] > 0 ? 1 : -1);
      worst = std::max(worst, -d);
    }
  CHECK(worst <= tol);
}

double longest_edge(const mesh::TetMesh& m) {
  double l = 0;
  for (int t = 0; t < m.num_tets(); ++t)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) l = std::max(l, (m.node(m.tets(t, i)) - m.node(m.tets(t, j))).norm());
  return l;
}

}  // namespace

TEST_SUITE("cut/cutter") {
  TEST_CASE("a blade swept fully across a box separates it into two pieces in one or several steps") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.3, 0.7);
    std::uniform_int_distribution<int> nsteps(1, 6);
    std::uniform_real_distribution<double> any(-1, 1);
    for (int trial = 0; trial < 80; ++trial) {
      CAPTURE(trial);
      Runner r(random_box(rng));
      const Vector3d c(u(rng), u(rng), u(rng));
      // Mostly upright planes, every third one in any direction.
      const Vector3d n = trial % 3 ? random_plane_normal(rng) : Vector3d(any(rng), any(rng), any(rng)).normalized();
      const double h = longest_edge(r.m);
      for (const auto& b : through_cut(c, n, nsteps(rng))) r.step(b);
      std::vector<int> comp;
      REQUIRE(test::components(r.m, &comp) == 2);
      check_sides(r.m, comp, c, n, 0.5 * h);
      int split = 0;
      for (const auto& rec : r.records) split += rec.edges_split;
      CHECK(split > 0);
    }
  }

  TEST_CASE("through-cuts stay valid and separate for any snap fraction and quality bound") {
    std::mt19937 rng(29);
    std::uniform_real_distribution<double> u(0.3, 0.7), any(-1, 1), snap(0.05, 0.3), bound(0, 12);
    std::uniform_int_distribution<int> nsteps(1, 12);
    for (int trial = 0; trial < 40; ++trial) {
      CAPTURE(trial);
      Runner r(random_box(rng, 5));
      r.opt.snap_fraction = snap(rng);
      r.opt.min_dihedral_deg = bound(rng);
      const Vector3d c(u(rng), u(rng), u(rng)), n = Vector3d(any(rng), any(rng), any(rng)).normalized();
      for (const auto& b : through_cut(c, n, nsteps(rng))) r.step(b);
      std::vector<int> comp;
      REQUIRE(test::components(r.m, &comp) == 2);
      check_sides(r.m, comp, c, n, 0.5 * longest_edge(r.m));
    }
  }

  TEST_CASE("a partial cut leaves one piece and continuing it completes the separation") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0.35, 0.65);
    for (int trial = 0; trial < 30; ++trial) {
      CAPTURE(trial);
      Runner r(random_box(rng));
      const Vector3d c(u(rng), u(rng), 0.5), n = random_plane_normal(rng);
      // The blade tip stops inside the box (0.2 below its centre), then goes on.
      for (const auto& b : through_cut(c, n, 3, 2.5, -0.2)) r.step(b);
      CHECK(test::components(r.m) == 1);
      int opened = 0;  // the cut opens behind the blade edge already
      for (const auto& rec : r.records) opened += rec.faces_separated;
      CHECK(opened > 0);
      for (const auto& b : through_cut(c, n, 2, -0.2, -2.5)) r.step(b);
      CHECK(test::components(r.m) == 2);
    }
  }

  TEST_CASE("a cut along existing faces snaps to nodes and splits exactly") {
    for (const Vector3d& n : {Vector3d(1, 0, 0), Vector3d(1, -1, 0).normalized(), Vector3d(0, 1, 0)}) {
      CAPTURE(n.transpose());
      mesh::BoxOptions box;
      box.nx = box.ny = box.nz = 4;
      Runner r(box);
      for (const auto& b : through_cut(Vector3d(0.5, 0.5, 0.5), n, 3)) r.step(b);
      for (const auto& rec : r.records) CHECK(rec.edges_split == 0);
      std::vector<int> comp;
      REQUIRE(test::components(r.m, &comp) == 2);
      double v[2] = {0, 0};
      for (int t = 0; t < r.m.num_tets(); ++t) v[comp[size_t(t)]] += mesh::signed_volume(r.m, t);
      CHECK(v[0] == doctest::Approx(0.5).epsilon(1e-13));
      CHECK(v[1] == doctest::Approx(0.5).epsilon(1e-13));
      // The new boundary: the box (area 6) plus both sides of the cut.
      const mesh::Surface surf = mesh::extract_surface(r.m);
      double area = 0;
      for (int f = 0; f < surf.faces.rows(); ++f)
        area += 0.5 * (r.m.node(surf.faces(f, 1)) - r.m.node(surf.faces(f, 0)))
                          .cross(r.m.node(surf.faces(f, 2)) - r.m.node(surf.faces(f, 0)))
                          .norm();
      const double cut_area = std::abs(n.x()) > 0.9 || std::abs(n.y()) > 0.9 ? 1.0 : std::sqrt(2.0);
      CHECK(area == doctest::Approx(6 + 2 * cut_area).epsilon(1e-12));
    }
  }

  TEST_CASE("cuts through a node and along an edge at oblique angles") {
    mesh::BoxOptions box;
    box.nx = box.ny = box.nz = 4;
    // Through the grid node (0.5, 0.5, 0.5); containing the vertical edge line x = y = 0.5.
    for (const Vector3d& n : {Vector3d(1, 0.37, 0.2), Vector3d(1, 0.3, 0), Vector3d(1, 1, 1)}) {
      CAPTURE(n.transpose());
      Runner r(box);
      for (const auto& b : through_cut(Vector3d(0.5, 0.5, 0.5), n, 4)) r.step(b);
      std::vector<int> comp;
      REQUIRE(test::components(r.m, &comp) == 2);
      check_sides(r.m, comp, Vector3d(0.5, 0.5, 0.5), n.normalized(), 0.5 * longest_edge(r.m));
    }
  }

  TEST_CASE("many tiny steps give the same kind of valid result as one big step") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.35, 0.65);
    for (int trial = 0; trial < 3; ++trial) {
      CAPTURE(trial);
      Runner r(random_box(rng, 3));
      const Vector3d c(u(rng), u(rng), u(rng)), n = random_plane_normal(rng);
      for (const auto& b : through_cut(c, n, 150, 1.6, -1.6)) r.step(b);
      CHECK(test::components(r.m) == 2);
    }
  }

  TEST_CASE("a trembling blade (back and forth) keeps the mesh valid and still cuts through") {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.35, 0.65), back(0.05, 0.3), fwd(0.1, 0.5);
    for (int trial = 0; trial < 16; ++trial) {
      CAPTURE(trial);
      Runner r(random_box(rng));
      r.expect_twins = false;  // the blade passes separated sides again
      const Vector3d c(u(rng), u(rng), u(rng)), n = random_plane_normal(rng);
      double h = 1.8;
      while (h > -1.8) {
        const double down = h - fwd(rng), up = down + back(rng);
        r.step(through_cut(c, n, 1, h, down)[0]);
        r.step(through_cut(c, n, 1, down, up)[0]);
        r.step(through_cut(c, n, 1, up, down)[0]);
        h = down;
      }
      CHECK(test::components(r.m) == 2);
    }
  }

  TEST_CASE("a second stroke crossing the first cut gives four pieces") {
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u(0.4, 0.6), tilt(-0.3, 0.3);
    std::uniform_int_distribution<int> nsteps(1, 5);
    for (int trial = 0; trial < 30; ++trial) {
      CAPTURE(trial);
      Runner r(random_box(rng, 5));
      r.expect_twins = false;  // the second blade re-splits separated sides independently
      const Vector3d c(u(rng), u(rng), u(rng));
      for (const auto& b : through_cut(c, Vector3d(1, tilt(rng), tilt(rng)), nsteps(rng))) r.step(b);
      CHECK(test::components(r.m) == 2);
      cut::begin_stroke(r.st);
      for (const auto& b : through_cut(c, Vector3d(tilt(rng), 1, tilt(rng)), nsteps(rng))) r.step(b);
      CHECK(test::components(r.m) == 4);
    }
  }

  TEST_CASE("repeating a finished cut changes nothing") {
    std::mt19937 rng(9);
    Runner r(random_box(rng));
    const auto blades = through_cut(Vector3d(0.45, 0.5, 0.5), Vector3d(1, 0.2, 0.1), 2);
    for (const auto& b : blades) r.step(b);
    const mesh::TetMesh done = r.m;
    for (const auto& b : blades) {
      const auto& rec = r.step(b);
      CHECK(rec.edges_split == 0);
      CHECK(rec.new_nodes.empty());
      CHECK(rec.changed_tets.empty());
    }
    CHECK(r.m.tets == done.tets);
    CHECK(test::components(r.m) == 2);
  }

  TEST_CASE("a cut reaching the locked interface stops there and warns") {
    std::mt19937 rng(13);
    for (int trial = 0; trial < 8; ++trial) {
      CAPTURE(trial);
      const mesh::BoxOptions box = random_box(rng);
      const mesh::TetMesh m0 = mesh::generate_box(box);
      std::vector<char> cuttable(size_t(m0.num_tets()));
      for (int t = 0; t < m0.num_tets(); ++t) {
        double z = 0;
        for (int k = 0; k < 4; ++k) z += m0.nodes(m0.tets(t, k), 2) / 4;
        cuttable[size_t(t)] = z > 0.5;
      }
      Runner r(box, cuttable);
      bool warned = false;
      for (const auto& b : through_cut(Vector3d(0.5, 0.5, 0.5), Vector3d(1, 0.3, 0.1), 3))
        warned = r.step(b).warnings.size() > 0 || warned;
      CHECK(warned);
      // The upper part is cut, but both halves still hang on the uncut lower part.
      CHECK(test::components(r.m) == 1);
      for (int v = 0; v < int(r.locked0.size()); ++v)
        if (r.locked0[size_t(v)]) CHECK(r.st.locked[size_t(v)] != 0);
    }
  }

  TEST_CASE("a triangular blade stabbed into the box leaves a valid connected mesh") {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(0.3, 0.7);
    for (int trial = 0; trial < 10; ++trial) {
      CAPTURE(trial);
      Runner r(random_box(rng));
      const Vector3d tip(u(rng), u(rng), u(rng));
      r.step(cut::sweep_triangle(tip, Vector3d(tip.x() - 0.3, 0.5, 1.4), Vector3d(tip.x() + 0.3, 0.5, 1.4)));
      CHECK(test::components(r.m) == 1);
    }
  }

  TEST_CASE("the same input twice gives identical output") {
    std::mt19937 rng(19);
    const mesh::BoxOptions box = random_box(rng);
    const auto blades = through_cut(Vector3d(0.52, 0.47, 0.5), Vector3d(1, 0.4, 0.2), 5);
    Runner a(box), b(box);
    for (const auto& s : blades) {
      const auto& ra = a.step(s);
      const auto& rb = b.step(s);
      CHECK(ra.edges_split == rb.edges_split);
      CHECK(ra.changed_tets == rb.changed_tets);
    }
    CHECK(a.m.nodes == b.m.nodes);
    CHECK(a.m.tets == b.m.tets);
  }

  TEST_CASE("a blade at rest or outside the body changes nothing") {
    mesh::BoxOptions box;
    Runner r(box);
    const mesh::TetMesh m0 = r.m;
    r.step(cut::sweep_segment(Vector3d(0.5, -1, 0.5), Vector3d(0.5, 2, 0.5), Vector3d(0.5, -1, 0.5),
                              Vector3d(0.5, 2, 0.5)));
    r.step(cut::sweep_segment(Vector3d(3, -1, 2), Vector3d(3, 2, 2), Vector3d(3, -1, -2), Vector3d(3, 2, -2)));
    CHECK(r.m.tets == m0.tets);
    CHECK(r.m.nodes == m0.nodes);
  }

  TEST_CASE("bad options and mismatched state are refused with a message") {
    mesh::BoxOptions box;
    mesh::TetMesh m = mesh::generate_box(box);
    CHECK_THROWS_AS(cut::make_cut_state(m, {1, 0}, {}), Error);
    auto st = cut::make_cut_state(m, std::vector<char>(size_t(m.num_tets()), 1),
                                  std::vector<char>(size_t(m.num_nodes()), 0));
    cut::CutOptions bad;
    bad.snap_fraction = 0.6;
    CHECK_THROWS_WITH_AS(cut::cut_step(m, st, {}, bad), doctest::Contains("snap_fraction"), Error);
    const Vector3d nan(std::nan(""), 0, 0);
    CHECK_THROWS_WITH_AS(cut::sweep_triangle(nan, Vector3d(1, 0, 0), Vector3d(0, 1, 0)), doctest::Contains("non-finite"),
                         Error);
    cut::SweptSurface hand;
    hand.triangles.push_back(Eigen::Matrix3d::Identity());
    hand.triangles[0](1, 2) = std::nan("");
    CHECK_THROWS_WITH_AS(cut::cut_step(m, st, hand), doctest::Contains("non-finite"), Error);
    st.locked.pop_back();
    CHECK_THROWS_WITH_AS(cut::cut_step(m, st, {}), doctest::Contains("make_cut_state"), Error);
  }
}
