#include "fem/anchoring.hpp"

#include <doctest/doctest.h>

#include <array>

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

// Nodes of the box face x = 0 of the first box.
std::vector<int> face_x0(const mesh::TetMesh& m) {
  std::vector<int> f;
  for (int v = 0; v < m.num_nodes(); ++v)
    if (m.nodes(v, 0) == 0 && m.nodes(v, 1) <= 1 && m.nodes(v, 2) <= 1 && m.nodes(v, 1) >= 0) f.push_back(v);
  return f;
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

  TEST_CASE("a part hanging by an edge or a node is not anchored, one joined by a face or two edges is") {
    const Eigen::Vector3d O(0, 0, 0);
    // The second box touches the first (whose face x = 0 is fixed) at...
    const mesh::TetMesh by_face = test::touching_boxes({O, {1, 0, 0}});
    const mesh::TetMesh by_edge = test::touching_boxes({O, {1, 1, 0}});
    const mesh::TetMesh by_node = test::touching_boxes({O, {1, 1, 1}});
    CHECK_NOTHROW(fem::check_anchored(by_face, {}, flags(by_face.num_nodes(), face_x0(by_face)), "test"));
    CHECK(fem::connected_parts(by_edge).count == 1);  // one part by shared nodes: why the old check missed it
    CHECK_THROWS_WITH_AS(fem::check_anchored(by_edge, {}, flags(by_edge.num_nodes(), face_x0(by_edge)), "test"),
                         doctest::Contains("hangs by the edge through nodes"), Error);
    CHECK_THROWS_WITH_AS(fem::check_anchored(by_node, {}, flags(by_node.num_nodes(), face_x0(by_node)), "test"),
                         doctest::Contains("hangs by node"), Error);
    const fem::Anchoring A = fem::anchor_parts(by_edge, {}, flags(by_edge.num_nodes(), face_x0(by_edge)));
    REQUIRE(A.parts.size() == 2);
    CHECK(A.parts[0].anchored);
    CHECK(!A.parts[1].anchored);
    CHECK(A.parts[1].pin == fem::Anchoring::Pin::line);
    CHECK(A.parts[1].through_shared);
    CHECK(A.parts[1].tets == 48);
    // The hinge edge's nodes lie on x = 1, y = 1.
    for (int v : {A.parts[1].pin_a, A.parts[1].pin_b}) {
      CHECK(by_edge.nodes(v, 0) == 1.0);
      CHECK(by_edge.nodes(v, 1) == 1.0);
    }
    // A box between two fixed boxes, touching each along an edge on a
    // different line: pinned at four nodes not on one line, anchored.
    const mesh::TetMesh bridge = test::touching_boxes({O, {1, 1, 0}, {2, 0, 1}});
    std::vector<int> fixed = face_x0(bridge);
    for (int v = 0; v < bridge.num_nodes(); ++v)
      if (bridge.nodes(v, 0) == 3) fixed.push_back(v);  // the far face of the third box
    const fem::Anchoring B = fem::anchor_parts(bridge, {}, flags(bridge.num_nodes(), fixed));
    REQUIRE(B.parts.size() == 3);
    for (const auto& P : B.parts) CHECK(P.anchored);
    CHECK_NOTHROW(fem::check_anchored(bridge, {}, flags(bridge.num_nodes(), fixed), "test"));
    // Anchoring spreads along a chain joined by faces, not along one joined by an edge.
    const mesh::TetMesh chain = test::touching_boxes({O, {1, 0, 0}, {2, 0, 0}, {3, 1, 0}});
    const fem::Anchoring C = fem::anchor_parts(chain, {}, flags(chain.num_nodes(), face_x0(chain)));
    REQUIRE(C.parts.size() == 2);
    CHECK(C.parts[0].anchored);
    CHECK(C.parts[0].tets == 3 * 48);
    CHECK(!C.parts[1].anchored);
  }

  TEST_CASE("sizes and ids are checked") {
    const mesh::TetMesh m = test::jittered_box(1, 1, 1, 0, 1);
    CHECK_THROWS_AS(fem::check_anchored(m, {}, {1, 1}, "test"), Error);
    CHECK_THROWS_AS(fem::connected_parts(m, {7}), Error);
  }
}
