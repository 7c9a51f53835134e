#include "fem/anchoring.hpp"

#include <doctest/doctest.h>

#include "core/error.hpp"
#include "fem_fixtures.hpp"

using namespace softcut;

namespace {

// Two boxes side by side that share no node: [0,1]^3 and [2,3]x[0,1]x[0,1].
mesh::TetMesh two_boxes() {
  const mesh::TetMesh a = test::jittered_box(2, 2, 2, 0, 1);
  mesh::TetMesh b = a;
  b.nodes.col(0).array() += 2.0;
  mesh::TetMesh m;
  m.nodes.resize(2 * a.num_nodes(), 3);
  m.nodes << a.nodes, b.nodes;
  m.tets.resize(2 * a.num_tets(), 4);
  m.tets << a.tets, (b.tets.array() + a.num_nodes()).matrix();
  m.labels = Eigen::VectorXi::Zero(m.num_tets());
  return m;
}

std::vector<char> flags(int nn, const std::vector<int>& ids) {
  std::vector<char> f(size_t(nn), 0);
  for (int i : ids) f[size_t(i)] = 1;
  return f;
}

}  // namespace

TEST_SUITE("fem/anchoring") {
  TEST_CASE("parts of a mesh and of tet subsets") {
    const mesh::TetMesh m = two_boxes();
    const fem::Parts p = fem::connected_parts(m);
    CHECK(p.count == 2);
    CHECK(p.tet_count == std::vector<int>{48, 48});
    CHECK(p.node_part[0] == 0);
    CHECK(p.node_part[27] == 1);
    const fem::Parts one = fem::connected_parts(m, {50, 51});
    CHECK(one.count == 1);
    CHECK(one.node_part[0] == -1);
    int used = 0;
    for (int q : one.node_part) used += q >= 0;
    CHECK(used >= 5);
  }

  TEST_CASE("a part without fixed nodes is named with its node, tet count and box") {
    const mesh::TetMesh m = two_boxes();
    const int nn = m.num_nodes();
    // Face x = 0 of the first box fixed (nodes 0, 3, 6, ... have i = 0).
    std::vector<int> face;
    for (int i = 0; i < 27; ++i)
      if (m.nodes(i, 0) == 0) face.push_back(i);
    CHECK_THROWS_WITH_AS(fem::check_anchored(m, {}, flags(nn, face), "test"),
                         doctest::Contains("containing node 27 (48 tets, bounding box [2, 0, 0] .. [3, 1, 1] m, "
                                           "one of 2 parts) has no fixed node"),
                         Error);
    std::vector<int> both = face;
    for (int i : face) both.push_back(i + 27);
    CHECK_NOTHROW(fem::check_anchored(m, {}, flags(nn, both), "test"));
  }

  TEST_CASE("one fixed point or a line of fixed nodes leaves a rotation free") {
    const mesh::TetMesh m = test::jittered_box(2, 2, 2, 0, 1);
    const int nn = m.num_nodes();
    CHECK_THROWS_WITH_AS(fem::check_anchored(m, {}, flags(nn, {4}), "test"),
                         doctest::Contains("fixed only at node 4"), Error);
    // Nodes 0, 1, 2 lie on the x axis.
    CHECK_THROWS_WITH_AS(fem::check_anchored(m, {}, flags(nn, {0, 1, 2}), "test"),
                         doctest::Contains("line through nodes 0 and 2"), Error);
    CHECK_NOTHROW(fem::check_anchored(m, {}, flags(nn, {0, 2, 3}), "test"));
  }

  TEST_CASE("sizes and ids are checked") {
    const mesh::TetMesh m = test::jittered_box(1, 1, 1, 0, 1);
    CHECK_THROWS_AS(fem::check_anchored(m, {}, {1, 1}, "test"), Error);
    CHECK_THROWS_AS(fem::connected_parts(m, {7}), Error);
  }
}
