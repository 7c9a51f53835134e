#include "sim/selector.hpp"

#include <doctest/doctest.h>

#include "core/error.hpp"
#include "mesh/generate/box.hpp"

using V = Eigen::Vector3d;
using softcut::sim::NodeSelector;
using softcut::sim::TetSelector;
namespace mesh = softcut::mesh;
namespace sim = softcut::sim;

namespace {

// Unit cube, 2 x 2 x 2 cells: 27 nodes on a 0.5 m grid, 48 tets; tets with
// centroid x < 0.5 get label 2.
struct Cube {
  mesh::TetMesh m;
  mesh::Surface s;
  std::map<std::string, std::vector<int>> named{{"hole", {4, 13, 22}}};
  Cube() {
    mesh::BoxOptions o;
    o.nx = o.ny = o.nz = 2;
    m = mesh::generate_box(o);
    for (int t = 0; t < m.num_tets(); ++t) {
      double cx = 0;
      for (int k = 0; k < 4; ++k) cx += m.nodes(m.tets(t, k), 0) / 4;
      if (cx < 0.5) m.labels(t) = 2;
    }
    s = mesh::extract_surface(m);
  }
  sim::SelectContext ctx() const { return {m, s, named}; }
  std::vector<int> nodes(const NodeSelector& sel) const { return sim::select_nodes(sel, ctx(), "test"); }
  std::vector<int> tets(const TetSelector& sel) const { return sim::select_tets(sel, ctx(), "test"); }
  // Brute force: node ids whose rest position satisfies pred.
  template <class P>
  std::vector<int> where(P pred) const {
    std::vector<int> r;
    for (int n = 0; n < m.num_nodes(); ++n)
      if (pred(m.node(n))) r.push_back(n);
    return r;
  }
};

}  // namespace

TEST_SUITE("sim/selector") {
  TEST_CASE("geometric node selectors against brute force") {
    Cube c;
    const auto face_x0 = c.nodes(NodeSelector::box(V(-1, -1, -1), V(0, 1, 1)));
    CHECK(face_x0.size() == 9);
    CHECK(face_x0 == c.where([](const V& x) { return x.x() == 0; }));
    CHECK(c.nodes(NodeSelector::sphere(V(0, 0, 0), 0.5)).size() == 4);
    CHECK(c.nodes(NodeSelector::halfspace(V(0.5, 0, 0), V(2, 0, 0))) ==
          c.where([](const V& x) { return x.x() >= 0.5; }));
    NodeSelector all;
    CHECK(c.nodes(all).size() == 27);
  }

  TEST_CASE("labels, surfaces, lists and named sets") {
    Cube c;
    NodeSelector lab;
    lab.kind = NodeSelector::Kind::label;
    lab.label = 2;
    CHECK(c.nodes(lab) == c.where([](const V& x) { return x.x() <= 0.5; }));
    NodeSelector surf;
    surf.kind = NodeSelector::Kind::surface;
    CHECK(c.nodes(surf) == c.where([](const V& x) { return x != V(0.5, 0.5, 0.5); }));
    surf.label = 2;  // boundary of the half cube x <= 0.5: all 18 of its nodes
    CHECK(c.nodes(surf) == c.where([](const V& x) { return x.x() <= 0.5; }));
    CHECK(c.nodes(NodeSelector::list({5, 3, 5})) == std::vector<int>{3, 5});
    NodeSelector hole;
    hole.kind = NodeSelector::Kind::named;
    hole.name = "hole";
    CHECK(c.nodes(hole) == std::vector<int>{4, 13, 22});
  }

  TEST_CASE("set algebra: union, intersection, difference") {
    Cube c;
    const NodeSelector x0 = NodeSelector::box(V(-1, -1, -1), V(0, 1, 1));
    const NodeSelector y0 = NodeSelector::box(V(-1, -1, -1), V(1, 0, 1));
    const NodeSelector z0 = NodeSelector::box(V(-1, -1, -1), V(1, 1, 0));
    using K = NodeSelector::Kind;
    CHECK(c.nodes(NodeSelector::combine(K::union_of, {x0, y0})) ==
          c.where([](const V& x) { return x.x() == 0 || x.y() == 0; }));
    CHECK(c.nodes(NodeSelector::combine(K::intersection, {x0, y0})) ==
          c.where([](const V& x) { return x.x() == 0 && x.y() == 0; }));
    CHECK(c.nodes(NodeSelector::combine(K::difference, {x0, y0, z0})) ==
          c.where([](const V& x) { return x.x() == 0 && x.y() != 0 && x.z() != 0; }));
    // Nested: (x0 | y0) & z0
    CHECK(c.nodes(NodeSelector::combine(K::intersection, {NodeSelector::combine(K::union_of, {x0, y0}), z0})).size() == 5);
  }

  TEST_CASE("tet selectors use centroids") {
    Cube c;
    CHECK(c.tets(TetSelector::of(TetSelector::Kind::all)).size() == 48);
    CHECK(c.tets(TetSelector::of(TetSelector::Kind::none)).empty());
    TetSelector half = TetSelector::of(TetSelector::Kind::halfspace);
    half.point = V(0.5, 0, 0);
    half.normal = V(1, 0, 0);
    CHECK(c.tets(half).size() == 24);
    TetSelector lab = TetSelector::of(TetSelector::Kind::label);
    lab.label = 2;
    const auto left = c.tets(lab);
    CHECK(left.size() == 24);
    TetSelector both = TetSelector::of(TetSelector::Kind::union_of);
    both.children = {half, lab};
    CHECK(c.tets(both).size() == 48);
    TetSelector list = TetSelector::of(TetSelector::Kind::tets);
    list.ids = {7, 2, 7};
    CHECK(c.tets(list) == std::vector<int>{2, 7});
  }

  TEST_CASE("errors name the item and the problem") {
    Cube c;
    using softcut::Error;
    NodeSelector bad = NodeSelector::list({3, 99});
    bad.where = "liver.lua:12";
    CHECK_THROWS_WITH_AS(sim::select_nodes(bad, c.ctx(), "fixed"),
                         doctest::Contains("liver.lua:12: fixed: node id 99 (entry 2) is out of range"), Error);
    NodeSelector lab;
    lab.kind = NodeSelector::Kind::label;
    lab.label = 9;
    CHECK_THROWS_WITH_AS(c.nodes(lab), doctest::Contains("no tet has label 9"), Error);
    NodeSelector named;
    named.kind = NodeSelector::Kind::named;
    named.name = "bone";
    CHECK_THROWS_WITH_AS(c.nodes(named), doctest::Contains("hole"), Error);
    CHECK_THROWS_AS(c.nodes(NodeSelector::sphere(V::Zero(), -1)), Error);
    CHECK_THROWS_AS(c.nodes(NodeSelector::box(V::Ones(), V::Zero())), Error);
    CHECK_THROWS_AS(c.nodes(NodeSelector::combine(NodeSelector::Kind::union_of, {})), Error);
    TetSelector t = TetSelector::of(TetSelector::Kind::tets);
    t.ids = {48};
    CHECK_THROWS_WITH_AS(c.tets(t), doctest::Contains("tet id 48"), Error);
  }
}
