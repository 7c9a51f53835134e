#pragma once
// The benchmarks' test body, written once: a box of nx x ny x nz cells (six
// tets each, mesh::generate_box) of soft tissue (E = 3 kPa, nu = 0.45, the
// paper's order of magnitude), its interior nodes jittered, the nodes on one
// face fixed. Each bench picks the size, resolution and face its baseline
// needs (hybrid: 2n x n x n, 10 x 5 x 5 cm, x = 0 fixed; cut: a 1 m cube,
// z = 0 fixed).
//
//   const BoxProblem b = box_problem({.cells = {42, 21, 21}, .size = {0.1, 0.05, 0.05}, .jitter = 0.1});
//   fem::solve_whole_mesh(b.mesh, b.materials, b.fixed_mask, loads);
#include <Eigen/Core>
#include <array>
#include <vector>

#include "fem/material.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::bench {

struct BoxSpec {
  std::array<int, 3> cells{4, 4, 4};                      // per axis, >= 1
  Eigen::Vector3d size = Eigen::Vector3d::Ones();         // m; the box spans [0, size]
  double jitter = 0;                                      // interior nodes, x cell size (< 0.25)
  int fixed_axis = 0;                                     // nodes at coordinate 0 on this axis fixed; -1: none
};

struct BoxProblem {
  mesh::TetMesh mesh;
  std::vector<fem::Material> materials;  // (tets) all E = 3 kPa, nu = 0.45
  std::vector<int> fixed;                // node ids on the fixed face, increasing
  std::vector<char> fixed_mask;          // (nodes) 1 on the fixed face
};

BoxProblem box_problem(const BoxSpec& spec);

}  // namespace softcut::bench
