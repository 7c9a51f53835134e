#include "mesh/tet_mesh.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "mesh/generate/box.hpp"

using namespace softcut;
using namespace softcut::mesh;

namespace {

TetMesh unit_tet() {
  TetMesh m;
  m.nodes.resize(4, 3);
  m.nodes << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.tets.resize(1, 4);
  m.tets << 0, 1, 2, 3;
  return m;
}

std::string error_of(TetMesh m) {
  Diagnostics d;
  try {
    validate(m, "in.msh", d);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_SUITE("mesh/tet_mesh") {
  TEST_CASE("signed volume: positive for the documented orientation, 1/6 for the unit corner") {
    const TetMesh m = unit_tet();
    CHECK(signed_volume(m, 0) == doctest::Approx(1.0 / 6));
    CHECK(signed_volume(m.node(0), m.node(1), m.node(3), m.node(2)) == doctest::Approx(-1.0 / 6));
  }

  TEST_CASE("kTetFaces are outward for a positive tet") {
    const TetMesh m = unit_tet();
    const Eigen::Vector3d centroid = m.nodes.colwise().mean();
    for (int f = 0; f < 4; ++f) {
      const Eigen::Vector3d a = m.node(kTetFaces[f][0]), b = m.node(kTetFaces[f][1]), c = m.node(kTetFaces[f][2]);
      // The fourth point (the centroid) lies behind every face.
      CHECK(signed_volume(a, b, c, centroid) < 0);
    }
  }

  TEST_CASE("validate flips exactly the negative tets and counts them") {
    BoxOptions o;
    o.nx = o.ny = o.nz = 2;
    TetMesh m = generate_box(o);
    const double v0 = total_volume(m);
    int flipped = 0;
    for (int t = 0; t < m.num_tets(); t += 3, ++flipped) std::swap(m.tets(t, 0), m.tets(t, 1));
    Diagnostics d;
    const auto r = validate(m, "gen", d);
    CHECK(r.reoriented == flipped);
    REQUIRE(d.warnings.size() == 1);
    CHECK(d.warnings[0].find(std::to_string(flipped)) != std::string::npos);
    for (int t = 0; t < m.num_tets(); ++t) CHECK(signed_volume(m, t) > 0);
    CHECK(total_volume(m) == doctest::Approx(v0));
    CHECK(m.labels.size() == m.num_tets());
    // Second pass: nothing to do, no warnings.
    Diagnostics d2;
    CHECK(validate(m, "gen", d2).reoriented == 0);
    CHECK(d2.warnings.empty());
  }

  TEST_CASE("validate names the bad element or node") {
    TetMesh m = unit_tet();
    m.nodes(2, 1) = std::nan("");
    CHECK(error_of(m).find("in.msh: node 2 has a non-finite coordinate") == 0);

    m = unit_tet();
    m.tets(0, 3) = 7;
    CHECK(error_of(m).find("tetrahedron 0 refers to node 7") != std::string::npos);
    m.tets(0, 3) = -1;
    CHECK(error_of(m).find("refers to node -1") != std::string::npos);

    m = unit_tet();
    m.tets(0, 3) = 1;
    CHECK(error_of(m).find("uses node 1 twice") != std::string::npos);

    m = unit_tet();
    m.nodes.row(3) << 0.5, 0.5, 0;  // in the plane of the other three
    CHECK(error_of(m).find("tetrahedron 0 (nodes 0 1 2 3) is degenerate") != std::string::npos);

    m = unit_tet();
    m.labels = Eigen::VectorXi::Zero(3);
    CHECK(error_of(m).find("3 labels for 1 tetrahedra") != std::string::npos);
  }

  TEST_CASE("unreferenced nodes are reported once, keep their ids") {
    TetMesh m = unit_tet();
    m.nodes.conservativeResize(6, 3);
    m.nodes.row(4) << 5, 5, 5;
    m.nodes.row(5) << 6, 6, 6;
    Diagnostics d;
    const auto r = validate(m, "in.msh", d);
    CHECK(r.unreferenced == std::vector<int>{4, 5});
    REQUIRE(d.warnings.size() == 1);
    CHECK(d.warnings[0].find("2 node(s) are used by no tetrahedron (first: 4)") != std::string::npos);
    CHECK(m.num_nodes() == 6);
    const auto used = referenced_nodes(m);
    CHECK(used == std::vector<char>{1, 1, 1, 1, 0, 0});
  }
}
