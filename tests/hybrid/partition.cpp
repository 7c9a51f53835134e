#include "hybrid/partition.hpp"

#include <doctest/doctest.h>

#include <random>

#include "fixtures.hpp"
#include "../fem/fem_fixtures.hpp"
#include "mesh/surface.hpp"

using namespace softcut;
using namespace softcut::hybrid;

TEST_SUITE("hybrid/partition") {
  TEST_CASE("node sets follow their definitions on random meshes and partitions") {
    std::mt19937 rng(1);
    for (int trial = 0; trial < 30; ++trial) {
      test::HybridCase c = test::random_case(rng, trial % 6);
      const mesh::TetMesh& m = c.mesh;
      const Partition& p = c.partition;
      // Brute force per node, independent of make_partition's bookkeeping.
      const auto boundary = mesh::extract_surface(m);
      std::vector<char> on_boundary(size_t(m.num_nodes()), 0);
      for (int f = 0; f < boundary.faces.rows(); ++f)
        for (int k = 0; k < 3; ++k) on_boundary[size_t(boundary.faces(f, k))] = 1;
      int total = 0;
      for (int v = 0; v < m.num_nodes(); ++v) {
        bool op = false, non = false;
        for (int t = 0; t < m.num_tets(); ++t)
          for (int k = 0; k < 4; ++k)
            if (m.tets(t, k) == v) (p.operational_tet[size_t(t)] ? op : non) = true;
        NodeSet want = !op && !non               ? NodeSet::unused
                       : c.fixed_mask[size_t(v)] ? NodeSet::fixed
                       : op && non               ? NodeSet::interface
                       : op                      ? NodeSet::operational
                       : on_boundary[size_t(v)]  ? NodeSet::surface
                                                 : NodeSet::interior;
        CHECK(p.node_set[size_t(v)] == want);
        total += want != NodeSet::unused;
      }
      const auto& n = p.counts;
      CHECK(n.fixed + n.operational + n.interface + n.surface + n.interior == total);
      CHECK(n.operational_tets + n.nonoperational_tets == m.num_tets());
      CHECK(int(p.surface.size()) == n.surface);
      CHECK(std::is_sorted(p.interface.begin(), p.interface.end()));
    }
  }

  TEST_CASE("region selectors test tet centroids") {
    mesh::BoxOptions o;
    o.nx = o.ny = o.nz = 2;  // unit cube, 48 tets
    const mesh::TetMesh m = mesh::generate_box(o);
    auto count = [](const std::vector<char>& mask) { return int(std::count(mask.begin(), mask.end(), 1)); };
    CHECK(count(tets_in_half_space(m, Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(1, 0, 0))) == 24);
    CHECK(count(tets_in_box(m, Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.5, 0.5, 0.5))) == 6);
    CHECK(count(tets_in_sphere(m, Eigen::Vector3d(0.5, 0.5, 0.5), 10)) == 48);
    CHECK(count(tets_in_sphere(m, Eigen::Vector3d(5, 5, 5), 1)) == 0);
    CHECK(count(tets_with_label(m, 1)) == 48);
    CHECK(count(tets_from_list(m, {0, 3, 3})) == 2);
    CHECK_THROWS_WITH_AS(tets_from_list(m, {48}), doctest::Contains("tet id 48 is out of range"), Error);
  }

  TEST_CASE("unused nodes are in no set, and degenerate regions work") {
    mesh::BoxOptions o;
    o.nx = 3, o.ny = o.nz = 2;
    mesh::TetMesh m = mesh::generate_box(o);
    m.nodes.conservativeResize(m.num_nodes() + 1, 3);
    m.nodes.row(m.num_nodes() - 1) = Eigen::RowVector3d(9, 9, 9);
    std::vector<int> fixed;
    for (int v = 0; v < m.num_nodes() - 1; ++v)
      if (m.nodes(v, 0) == 0) fixed.push_back(v);
    fixed.push_back(m.num_nodes() - 1);  // fixing an unused node is harmless
    const Partition none = make_partition(m, {}, fixed);
    CHECK(none.node_set.back() == NodeSet::unused);
    CHECK(none.counts.unused == 1);
    CHECK(none.operational.empty());
    CHECK(none.interface.empty());
    CHECK(none.counts.surface + none.counts.interior + none.counts.fixed == m.num_nodes() - 1);
    const Partition all = make_partition(m, std::vector<char>(size_t(m.num_tets()), 1), fixed);
    CHECK(all.surface.empty());
    CHECK(all.interior.empty());
    CHECK(all.counts.operational + all.counts.fixed == m.num_nodes() - 1);
    CHECK(describe(all.counts).find("nonoperational 0 nodes") != std::string::npos);
  }

  TEST_CASE("a part hanging by an edge is refused with its region and the hinge, one joined by a face is not") {
    const mesh::TetMesh m = test::touching_boxes({Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 1, 0)});
    std::vector<int> fixed;
    for (int v = 0; v < m.num_nodes(); ++v)
      if (m.nodes(v, 0) == 0) fixed.push_back(v);
    std::vector<char> op(size_t(m.num_tets()), 0);
    op[size_t(m.num_tets() - 1)] = 1;  // one operational tet in the hanging box
    try {
      make_partition(m, op, fixed);
      FAIL("expected an error");
    } catch (const Error& e) {
      const std::string msg = e.what();
      CHECK(msg.find("48 tets: 1 operational, 47 nonoperational") != std::string::npos);
      CHECK(msg.find("hangs by the edge through nodes") != std::string::npos);
      CHECK(msg.find("join it through a face") != std::string::npos);
    }
    const mesh::TetMesh joined = test::touching_boxes({Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 0, 0)});
    std::vector<int> fixed2;
    for (int v = 0; v < joined.num_nodes(); ++v)
      if (joined.nodes(v, 0) == 0) fixed2.push_back(v);
    CHECK_NOTHROW(make_partition(joined, {}, fixed2));
  }

  TEST_CASE("a part of the body without fixed nodes is named in the error") {
    mesh::BoxOptions o;
    o.nx = o.ny = o.nz = 2;
    const mesh::TetMesh a = mesh::generate_box(o);
    mesh::TetMesh m = a;  // two disjoint cubes; the second at x in [3, 4]
    m.nodes.conservativeResize(2 * a.num_nodes(), 3);
    m.nodes.bottomRows(a.num_nodes()) = a.nodes.rowwise() + Eigen::RowVector3d(3, 0, 0);
    m.tets.conservativeResize(2 * a.num_tets(), 4);
    m.tets.bottomRows(a.num_tets()) = a.tets.array() + a.num_nodes();
    m.labels = Eigen::VectorXi::Ones(m.num_tets());
    std::vector<int> fixed;
    for (int v = 0; v < a.num_nodes(); ++v)
      if (a.nodes(v, 0) == 0) fixed.push_back(v);
    std::vector<char> op(size_t(m.num_tets()), 0);
    for (int t = a.num_tets(); t < a.num_tets() + 5; ++t) op[size_t(t)] = 1;
    try {
      make_partition(m, op, fixed);
      FAIL("expected an error");
    } catch (const Error& e) {
      const std::string msg = e.what();
      CHECK(msg.find("node " + std::to_string(a.num_nodes())) != std::string::npos);
      CHECK(msg.find("48 tets: 5 operational, 43 nonoperational") != std::string::npos);
      CHECK(msg.find("operational and nonoperational regions") != std::string::npos);
      CHECK(msg.find("[3, 0, 0] .. [4, 1, 1]") != std::string::npos);
      CHECK(msg.find("no fixed node") != std::string::npos);
    }
    // Fixed nodes on one line only: still singular.
    std::vector<int> line;
    for (int v = 0; v < a.num_nodes(); ++v)
      if (a.nodes(v, 0) == 0 && a.nodes(v, 1) == 0) line.push_back(v);
    CHECK_THROWS_WITH_AS(make_partition(a, {}, line), doctest::Contains("all on one line"), Error);
    CHECK_THROWS_WITH_AS(make_partition(a, {}, {a.num_nodes()}), doctest::Contains("out of range"), Error);
    CHECK_THROWS_WITH_AS(make_partition(a, {1, 0}, fixed), doctest::Contains("mask has 2 entries"), Error);
  }
}
