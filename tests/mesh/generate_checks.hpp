#pragma once
// Invariants every generated (or voxel) mesh must satisfy, shared by the
// generate_*.cpp and label_volume.cpp suites.
#include <doctest/doctest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <map>
#include <utility>

#include "mesh/surface.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::test {

struct SurfaceTopology {
  int faces = 0, edges = 0, vertices = 0;
  int odd_edges = 0;          // surface edges not in exactly two surface faces
  int misoriented_edges = 0;  // edges traversed twice in the same direction
  int euler = 0;              // V - E + F
  double volume = 0;          // enclosed volume by the divergence theorem, m^3
};

inline SurfaceTopology surface_topology(const mesh::TetMesh& m) {
  const mesh::Surface s = mesh::extract_surface(m);
  SurfaceTopology t;
  t.faces = int(s.faces.rows());
  t.vertices = int(s.nodes.size());
  std::map<std::pair<int, int>, int> count, directed;
  Eigen::Vector3d ref = Eigen::Vector3d::Zero();
  for (int v : s.nodes) ref += m.node(v);
  ref /= std::max<size_t>(1, s.nodes.size());
  for (Eigen::Index f = 0; f < s.faces.rows(); ++f) {
    const Eigen::Vector3d a = m.node(s.faces(f, 0)) - ref, b = m.node(s.faces(f, 1)) - ref,
                          c = m.node(s.faces(f, 2)) - ref;
    t.volume += a.dot(b.cross(c)) / 6;
    for (int e = 0; e < 3; ++e) {
      const int p = s.faces(f, e), q = s.faces(f, (e + 1) % 3);
      ++count[{std::min(p, q), std::max(p, q)}];
      ++directed[{p, q}];
    }
  }
  t.edges = int(count.size());
  for (const auto& [e, n] : count) t.odd_edges += n != 2;
  for (const auto& [e, n] : directed) t.misoriented_edges += n != 1;
  t.euler = t.vertices - t.edges + t.faces;
  return t;
}

// Every tet positive (relative to its size), every node used, surface closed,
// manifold and consistently oriented with the given Euler characteristic, and
// the surface encloses exactly the summed tet volume.
inline void check_solid(const mesh::TetMesh& m, int euler) {
  REQUIRE(m.num_tets() > 0);
  CHECK(m.labels.size() == m.num_tets());
  int bad = 0;
  for (int t = 0; t < m.num_tets(); ++t) {
    double l = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) l = std::max(l, (m.node(m.tets(t, i)) - m.node(m.tets(t, j))).norm());
    bad += !(mesh::signed_volume(m, t) > 1e-3 * l * l * l);
  }
  CHECK(bad == 0);
  const auto used = mesh::referenced_nodes(m);
  CHECK(std::count(used.begin(), used.end(), 0) == 0);
  const SurfaceTopology s = surface_topology(m);
  CHECK(s.odd_edges == 0);
  CHECK(s.misoriented_edges == 0);
  CHECK(s.euler == euler);
  const double v = mesh::total_volume(m);
  CHECK(s.volume == doctest::Approx(v).epsilon(1e-12));
}

}  // namespace softcut::test
