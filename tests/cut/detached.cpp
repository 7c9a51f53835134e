#include "cut/detached.hpp"

#include <doctest/doctest.h>

#include <random>

#include "core/error.hpp"
#include "cut/cutter.hpp"
#include "mesh/generate/box.hpp"
#include "mesh_checks.hpp"
#include "../fem/fem_fixtures.hpp"

using namespace softcut;
using Eigen::Vector3d;

namespace {

std::vector<char> fixed_where(const mesh::TetMesh& m, bool (*pred)(const Vector3d&)) {
  std::vector<char> f(size_t(m.num_nodes()), 0);
  for (int v = 0; v < m.num_nodes(); ++v) f[size_t(v)] = pred(m.node(v));
  return f;
}

mesh::TetMesh unit_box(int n) {
  mesh::BoxOptions b;
  b.nx = b.ny = b.nz = n;
  return mesh::generate_box(b);
}

// Blade spanning the unit box in the plane through c with normal n, lowered
// from above the box to below it in `steps` steps.
std::vector<cut::SweptSurface> plane_cut(const Vector3d& c, const Vector3d& n, int steps) {
  const Vector3d b = n.cross(Vector3d::UnitZ()).normalized();
  Vector3d d = n.cross(b).normalized();
  if (d.z() < 0) d = -d;
  std::vector<cut::SweptSurface> out;
  for (int k = 0; k < steps; ++k) {
    const double h0 = 2.5 - 5.0 * k / steps, h1 = 2.5 - 5.0 * (k + 1) / steps;
    out.push_back(cut::sweep_segment(c + h0 * d - 2.5 * b, c + h0 * d + 2.5 * b, c + h1 * d - 2.5 * b,
                                     c + h1 * d + 2.5 * b));
  }
  return out;
}

}  // namespace

TEST_SUITE("cut/detached") {
  TEST_CASE("an anchored box has no detached piece - an unfixed one is one whole piece") {
    const mesh::TetMesh m = unit_box(3);
    CHECK(cut::find_detached(m, fixed_where(m, [](const Vector3d& p) { return p.x() == 0.0; })).empty());
    const auto pieces = cut::find_detached(m, std::vector<char>(size_t(m.num_nodes()), 0));
    REQUIRE(pieces.size() == 1);
    CHECK(int(pieces[0].tets.size()) == m.num_tets());
    CHECK(int(pieces[0].nodes.size()) == m.num_nodes());
    CHECK(pieces[0].fixed_nodes == 0);
    CHECK_THROWS_AS(cut::find_detached(m, std::vector<char>(3, 0)), Error);
  }

  TEST_CASE("fixed nodes at one point or on one line do not anchor - three off a line do") {
    const mesh::TetMesh m = unit_box(2);  // nodes at 0, 0.5, 1 per axis
    auto node_at = [&](double x, double y, double z) {
      for (int v = 0; v < m.num_nodes(); ++v)
        if ((m.node(v) - Vector3d(x, y, z)).norm() < 1e-12) return v;
      FAIL("no node at ", x, " ", y, " ", z);
      return -1;
    };
    std::vector<char> f(size_t(m.num_nodes()), 0);
    f[size_t(node_at(0, 0, 0))] = 1;
    auto pieces = cut::find_detached(m, f);
    REQUIRE(pieces.size() == 1);
    CHECK(pieces[0].fixed_nodes == 1);
    f[size_t(node_at(0.5, 0, 0))] = f[size_t(node_at(1, 0, 0))] = 1;  // an edge of the box: a hinge
    pieces = cut::find_detached(m, f);
    REQUIRE(pieces.size() == 1);
    CHECK(pieces[0].fixed_nodes == 3);
    f[size_t(node_at(1, 0.5, 0.5))] = 1;  // off that line
    CHECK(cut::find_detached(m, f).empty());
  }

  TEST_CASE("of two separate boxes the unfixed one is the piece - with exactly its tets and nodes") {
    const mesh::TetMesh a = unit_box(2), b = unit_box(3);
    mesh::TetMesh m;
    const int na = a.num_nodes(), ta = a.num_tets();
    m.nodes.resize(na + b.num_nodes() + 1, 3);  // + one node used by no tet
    m.nodes.topRows(na) = a.nodes;
    m.nodes.middleRows(na, b.num_nodes()) = b.nodes.rowwise() + Eigen::RowVector3d(3, 0, 0);
    m.nodes.bottomRows(1) = Eigen::RowVector3d(9, 9, 9);
    m.tets.resize(ta + b.num_tets(), 4);
    m.tets.topRows(ta) = a.tets;
    m.tets.bottomRows(b.num_tets()) = b.tets.array() + na;
    m.labels = Eigen::VectorXi::Ones(m.num_tets());
    const auto pieces = cut::find_detached(m, fixed_where(m, [](const Vector3d& p) { return p.x() == 0.0; }));
    REQUIRE(pieces.size() == 1);
    REQUIRE(int(pieces[0].tets.size()) == b.num_tets());
    REQUIRE(int(pieces[0].nodes.size()) == b.num_nodes());
    for (size_t k = 0; k < pieces[0].tets.size(); ++k) CHECK(pieces[0].tets[k] == ta + int(k));
    for (size_t k = 0; k < pieces[0].nodes.size(); ++k) CHECK(pieces[0].nodes[k] == na + int(k));
  }

  TEST_CASE("a box hanging by an edge or a node is a piece, without the hinge nodes - one joined by a face is not") {
    for (const Vector3d& shift : {Vector3d(1, 1, 0), Vector3d(1, 1, 1), Vector3d(1, 0, 0)}) {
      const mesh::TetMesh m = test::touching_boxes({Vector3d::Zero(), shift});
      std::vector<char> fixed(size_t(m.num_nodes()), 0);
      for (int v = 0; v < m.num_nodes(); ++v) fixed[size_t(v)] = m.nodes(v, 0) == 0;
      const auto pieces = cut::find_detached(m, fixed);
      CAPTURE(shift.transpose());
      if (shift.y() == 0) {  // a face is shared: one rigid, anchored part
        CHECK(pieces.empty());
        continue;
      }
      REQUIRE(pieces.size() == 1);
      CHECK(pieces[0].tets.size() == 48);
      CHECK(pieces[0].fixed_nodes == 0);
      // Every node of the second box but the hinge: 27 less 3 (an edge of 2 cells) or 1.
      CHECK(pieces[0].nodes.size() == (shift.z() == 0 ? 24u : 26u));
      for (int v : pieces[0].nodes) CHECK(m.node(v).x() >= 1.0);
      for (int v : pieces[0].nodes) CHECK(!(m.nodes(v, 0) == 1.0 && m.nodes(v, 1) == 1.0 && (shift.z() == 0 || m.nodes(v, 2) == 1.0)));
    }
  }

  TEST_CASE("a through-cut near the free end of a box fixed at the other end frees exactly the far side") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> at(0.55, 0.8), tilt(-0.3, 0.3), jit(0.0, 0.2);
    std::uniform_int_distribution<int> cells(3, 5), steps(1, 4);
    for (int trial = 0; trial < 12; ++trial) {
      CAPTURE(trial);
      mesh::BoxOptions bo;
      bo.nx = cells(rng), bo.ny = cells(rng), bo.nz = cells(rng);
      bo.jitter = jit(rng);
      bo.seed = rng();
      mesh::TetMesh m = mesh::generate_box(bo);
      const std::vector<char> all(size_t(m.num_tets()), 1), none(size_t(m.num_nodes()), 0);
      cut::CutState st = cut::make_cut_state(m, all, none);
      const Vector3d c(at(rng), 0.5, 0.5), n = Vector3d(1, tilt(rng), tilt(rng)).normalized();
      for (const auto& blade : plane_cut(c, n, steps(rng))) cut::cut_step(m, st, blade);
      // Nodes made by cutting lie inside the box: x == 0 only for nodes on the fixed face.
      const std::vector<char> fixed = fixed_where(m, [](const Vector3d& p) { return p.x() == 0.0; });
      const auto pieces = cut::find_detached(m, fixed);
      // Independent: the face-connected components of the cut mesh.
      std::vector<int> comp;
      const int ncomp = test::components(m, &comp);
      REQUIRE(ncomp == 2);
      REQUIRE(pieces.size() == 1);
      const cut::DetachedPiece& p = pieces[0];
      CHECK(p.fixed_nodes == 0);
      std::vector<int> expect;
      int fixed_comp = -1;
      for (int v = 0; v < m.num_nodes(); ++v)
        if (fixed[size_t(v)])
          for (int t = 0; t < m.num_tets(); ++t)
            for (int k = 0; k < 4; ++k)
              if (m.tets(t, k) == v) fixed_comp = comp[size_t(t)];
      REQUIRE(fixed_comp >= 0);
      for (int t = 0; t < m.num_tets(); ++t)
        if (comp[size_t(t)] != fixed_comp) expect.push_back(t);
      CHECK(p.tets == expect);
      // Every node of the piece is on the far side of the plane (within an edge).
      const double h = 1.0 / std::min({bo.nx, bo.ny, bo.nz});
      for (int v : p.nodes) CHECK((m.node(v) - c).dot(n) > -h);
    }
  }
}
