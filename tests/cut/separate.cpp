#include "cut/separate.hpp"

#include <doctest/doctest.h>

#include "mesh_checks.hpp"

using namespace softcut;

namespace {

// Two tets sharing the face (0, 1, 2): apexes 3 above and 4 below.
mesh::TetMesh bipyramid() {
  mesh::TetMesh m;
  m.nodes.resize(5, 3);
  m.nodes << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.3, 0.3, 1, 0.3, 0.3, -1;
  m.tets.resize(2, 4);
  m.tets << 0, 1, 2, 3, 0, 2, 1, 4;
  m.labels = Eigen::VectorXi::Zero(2);
  return m;
}

}  // namespace

TEST_SUITE("cut/separate") {
  TEST_CASE("a face on the stroke's cut between two tets on opposite sides is separated") {
    mesh::TetMesh m = bipyramid();
    REQUIRE(mesh::signed_volume(m, 0) > 0);
    REQUIRE(mesh::signed_volume(m, 1) > 0);
    auto st = cut::make_cut_state(m, {1, 1}, std::vector<char>(5, 0));
    for (int v : {0, 1, 2}) st.cut_stroke[size_t(v)] = st.stroke;
    st.swept = cut::sweep_triangle(Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(3, -1, 0), Eigen::Vector3d(-1, 3, 0));
    cut::detail::Adjacency adj;
    adj.build(m, st.cuttable);
    int blocked = 0;
    const auto faces = cut::detail::find_cut_faces(m, adj, st, {0, 1}, {}, 0.15, blocked);
    REQUIRE(faces.size() == 1);
    CHECK(faces[0].key == cut::detail::FaceKey{0, 1, 2});
    CHECK(blocked == 0);
    cut::CutRecord rec;
    rec.nodes_before = 5;
    rec.tets_before = 2;
    const auto changed = cut::detail::separate(m, adj, st, faces, rec);
    CHECK(changed == std::vector<int>{1});  // the second tet takes the copies
    CHECK(m.num_nodes() == 8);
    CHECK(rec.faces_separated == 1);
    CHECK(rec.faces_pending == 0);
    CHECK(test::components(m) == 2);
    for (const auto& nn : rec.new_nodes) {
      CHECK(nn.duplicate);
      CHECK(m.node(nn.id) == m.node(nn.parent[0]));
    }
  }

  TEST_CASE("a locked node keeps the face joined and is counted and off-cut nodes keep it joined silently") {
    mesh::TetMesh m = bipyramid();
    std::vector<char> locked(5, 0);
    locked[1] = 1;
    auto st = cut::make_cut_state(m, {1, 1}, locked);
    for (int v : {0, 1, 2}) st.cut_stroke[size_t(v)] = st.stroke;
    st.swept = cut::sweep_triangle(Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(3, -1, 0), Eigen::Vector3d(-1, 3, 0));
    cut::detail::Adjacency adj;
    adj.build(m, st.cuttable);
    int blocked = 0;
    CHECK(cut::detail::find_cut_faces(m, adj, st, {0, 1}, {}, 0.15, blocked).empty());
    CHECK(blocked > 0);
    st.locked[1] = 0;
    st.cut_stroke[2] = -1;  // node 2 not on the cut: no face to cut
    blocked = 0;
    CHECK(cut::detail::find_cut_faces(m, adj, st, {0, 1}, {}, 0.15, blocked).empty());
    CHECK(blocked == 0);
  }

  TEST_CASE("a face whose centre is off the swept surface is not cut") {
    mesh::TetMesh m = bipyramid();
    auto st = cut::make_cut_state(m, {1, 1}, std::vector<char>(5, 0));
    for (int v : {0, 1, 2}) st.cut_stroke[size_t(v)] = st.stroke;
    // The blade covered only a corner far from the face centre (1/3, 1/3, 0).
    st.swept = cut::sweep_triangle(Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(0.05, -1, 0), Eigen::Vector3d(-1, 0.05, 0));
    cut::detail::Adjacency adj;
    adj.build(m, st.cuttable);
    int blocked = 0;
    CHECK(cut::detail::find_cut_faces(m, adj, st, {0, 1}, {}, 0.15, blocked).empty());
  }
}
