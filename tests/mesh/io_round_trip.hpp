#pragma once
// Round-trip checks shared by the writer suites: meshes that must come back
// from write_mesh -> read_mesh bit for bit.
#include <doctest/doctest.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <random>

#include "io_sample.hpp"
#include "mesh/generate/box.hpp"

namespace softcut::test {

inline void check_equal(const mesh::TetMesh& a, const mesh::TetMesh& b) {
  REQUIRE(a.num_nodes() == b.num_nodes());
  REQUIRE(a.num_tets() == b.num_tets());
  CHECK(a.nodes == b.nodes);  // exact, not approximate
  CHECK(a.tets == b.tets);
  CHECK(a.labels == b.labels);
}

// A jittered box with awkward coordinates (no short decimal form) and mixed
// labels, including negative and large ones.
inline mesh::TetMesh awkward_box() {
  mesh::BoxOptions o;
  o.nx = 3, o.ny = 2, o.nz = 4;
  o.min_corner = Eigen::Vector3d(-0.1 / 3, 1e-7, 12345.678);
  o.max_corner = Eigen::Vector3d(0.7, 0.2 + 1e-7, 12345.678 + 0.3);
  o.jitter = 0.2;
  o.seed = 11;
  mesh::TetMesh m = mesh::generate_box(o);
  std::mt19937 rng(3);
  const int choices[] = {0, 1, -5, 2147483647, -2147483647 - 1, 42};
  for (int t = 0; t < m.num_tets(); ++t) m.labels(t) = choices[rng() % 6];
  return m;
}

// write -> read -> equal, for the sample files, a plain box and an awkward box.
inline void check_round_trips(const std::string& ext) {
  const auto dir = scratch_dir("round_trip" + ext);
  Diagnostics diag;
  int k = 0;
  auto trip = [&](const mesh::TetMesh& m) {
    const auto path = dir / ("m" + std::to_string(k++) + ext);
    mesh::write_mesh(path, m);
    Diagnostics d;
    check_equal(mesh::read_mesh(path, d), m);
    // Nothing new to report: the mesh was already clean and oriented.
    for (const auto& w : d.warnings) CHECK(w.find("reoriented") == std::string::npos);
  };
  for (const char* name : {"sample_v22.msh", "sample_v41.msh", "sample.mesh", "sample_binary.vtk", "sample_zlib_uint64.vtu"})
    trip(mesh::read_mesh(mesh_data(name), diag));
  trip(mesh::generate_box(mesh::BoxOptions{}));
  trip(awkward_box());
  // A written file read and written again is byte-identical.
  const auto p1 = dir / ("again1" + ext), p2 = dir / ("again2" + ext);
  mesh::write_mesh(p1, awkward_box());
  mesh::write_mesh(p2, mesh::read_mesh(p1, diag));
  CHECK(slurp(p1) == slurp(p2));
}

}  // namespace softcut::test
