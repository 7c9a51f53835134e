#include "mesh/surface.hpp"

#include <doctest/doctest.h>

#include "core/error.hpp"
#include "mesh/generate/box.hpp"
#include "generate_checks.hpp"

using namespace softcut;
using namespace softcut::mesh;

TEST_SUITE("mesh/surface") {
  TEST_CASE("a single tet: four outward faces, four nodes") {
    TetMesh m;
    m.nodes.resize(4, 3);
    m.nodes << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
    m.tets.resize(1, 4);
    m.tets << 0, 1, 2, 3;
    const Surface s = extract_surface(m);
    CHECK(s.faces.rows() == 4);
    CHECK(s.nodes == std::vector<int>{0, 1, 2, 3});
    CHECK(test::surface_topology(m).volume == doctest::Approx(1.0 / 6));
  }

  TEST_CASE("box: 2 faces per boundary square, boundary lattice nodes only") {
    for (int n : {1, 2, 4}) {
      BoxOptions o;
      o.nx = n, o.ny = n + 1, o.nz = n + 2;
      const TetMesh m = generate_box(o);
      const Surface s = extract_surface(m);
      const int nx = o.nx, ny = o.ny, nz = o.nz;
      CHECK(s.faces.rows() == 4 * (nx * ny + ny * nz + nx * nz));
      const int all = (nx + 1) * (ny + 1) * (nz + 1), inner = (nx - 1) * (ny - 1) * (nz - 1);
      CHECK(int(s.nodes.size()) == all - inner);
      for (Eigen::Index f = 0; f < s.faces.rows(); ++f) {
        // The owning tet holds all three nodes.
        for (int k = 0; k < 3; ++k) CHECK((m.tets.row(s.face_tet(f)).array() == s.faces(f, k)).any());
      }
      test::check_solid(m, 2);
    }
  }

  TEST_CASE("a tet mask gives the boundary of the subset, the two halves share the cut faces") {
    BoxOptions o;
    o.nx = 4, o.ny = 2, o.nz = 2;
    const TetMesh m = generate_box(o);
    std::vector<char> left(size_t(m.num_tets())), right(size_t(m.num_tets()));
    for (int t = 0; t < m.num_tets(); ++t) {
      double cx = 0;
      for (int k = 0; k < 4; ++k) cx += m.nodes(m.tets(t, k), 0) / 4;
      left[size_t(t)] = cx < 0.5, right[size_t(t)] = cx >= 0.5;
    }
    const Surface all = extract_surface(m), l = extract_surface(m, left), r = extract_surface(m, right);
    // Each half is a 2x2x2 box; the cut square (2x2 cells) appears in both.
    CHECK(l.faces.rows() == 4 * (4 + 4 + 4));
    CHECK(r.faces.rows() == l.faces.rows());
    CHECK(l.faces.rows() + r.faces.rows() - all.faces.rows() == 2 * 2 * 2 * 2);
    for (Eigen::Index f = 0; f < l.faces.rows(); ++f) CHECK(left[size_t(l.face_tet(f))]);
  }

  TEST_CASE("group boundaries: the faces between groups once, outward from the inclusion, whatever its id") {
    // A 4^3 box with a 2x2x2 core of another group: the core's 6 sides of
    // 2x2 squares, 2 triangles each, normals pointing away from the core.
    BoxOptions o;
    o.nx = o.ny = o.nz = 4;
    const TetMesh m = generate_box(o);
    for (const int core_id : {0, 7, 1 << 30}) {
      CAPTURE(core_id);
      std::vector<int> group(size_t(m.num_tets()), core_id == 0 ? 3 : 0);
      for (int t = 0; t < m.num_tets(); ++t) {
        const Eigen::Vector3d c = 0.25 * (m.node(m.tets(t, 0)) + m.node(m.tets(t, 1)) + m.node(m.tets(t, 2)) +
                                          m.node(m.tets(t, 3)));
        if ((c.array() > 0.25).all() && (c.array() < 0.75).all()) group[size_t(t)] = core_id;
      }
      const Surface s = group_boundaries(m, group);
      REQUIRE(s.faces.rows() == 6 * 4 * 2);
      for (Eigen::Index f = 0; f < s.faces.rows(); ++f) {
        CHECK(group[size_t(s.face_tet(f))] == core_id);  // the inclusion's side
        const Eigen::Vector3d a = m.node(s.faces(f, 0)), b = m.node(s.faces(f, 1)), c = m.node(s.faces(f, 2));
        CHECK((b - a).cross(c - a).dot((a + b + c) / 3 - Eigen::Vector3d::Constant(0.5)) > 0);  // outward
      }
      CHECK(s.nodes.size() == 26);  // the core's boundary lattice: 3^3 - 1
    }
    CHECK(group_boundaries(m, {}).faces.rows() == 0);
    CHECK(group_boundaries(m, std::vector<int>(size_t(m.num_tets()), 2)).faces.rows() == 0);
    CHECK_THROWS_AS(group_boundaries(m, {1, 2}), softcut::Error);
  }

  TEST_CASE("vertex normals of a box corner point along the diagonal") {
    BoxOptions o;
    o.nx = o.ny = o.nz = 2;
    const TetMesh m = generate_box(o);
    const Surface s = extract_surface(m);
    const Eigen::MatrixX3d n = vertex_normals(m, s);
    const int corner = 2 + 3 * (2 + 3 * 2);  // (1, 1, 1)
    CHECK(n.row(corner).norm() == doctest::Approx(1));
    for (int c = 0; c < 3; ++c) CHECK(n(corner, c) > 0.3);
    CHECK(n.row(1 + 3 * (1 + 3 * 1)).norm() == 0);  // the interior node
    // Face centre of x = 1: normal +x.
    CHECK(n(2 + 3 * (1 + 3 * 1), 0) == doctest::Approx(1));
  }
}
