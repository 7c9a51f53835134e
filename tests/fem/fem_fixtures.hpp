#pragma once
// Meshes and helpers shared by the fem test suites (header only, no suite).
#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "fem/material.hpp"
#include "mesh/generate/box.hpp"

namespace softcut::test {

inline mesh::TetMesh jittered_box(int nx, int ny, int nz, double jitter, unsigned seed,
                                  Eigen::Vector3d size = Eigen::Vector3d::Ones()) {
  mesh::BoxOptions o;
  o.nx = nx;
  o.ny = ny;
  o.nz = nz;
  o.jitter = jitter;
  o.seed = seed;
  o.max_corner = size;
  return mesh::generate_box(o);
}

// Random materials per tet (E in [1e3, 1e5] Pa, nu in [0, 0.45]).
inline std::vector<fem::Material> random_materials(int ntet, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<fem::Material> mats(static_cast<size_t>(ntet));
  for (auto& m : mats) m = {1e3 * std::pow(100.0, u(rng)), 0.45 * u(rng)};
  return mats;
}

// Random subset of tet ids (each kept with probability `keep`, at least one).
inline std::vector<int> random_subset(int ntet, double keep, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<int> s;
  for (int t = 0; t < ntet; ++t)
    if (u(rng) < keep) s.push_back(t);
  if (s.empty()) s.push_back(0);
  return s;
}

// Splits tet t at its centroid as a cut splits tets: t keeps its id with one
// child, three children (ids num_tets(), +1, +2) and the centroid node are
// appended. Replacing one corner by an inner point keeps the orientation.
inline void split_at_centroid(mesh::TetMesh& m, int t) {
  const int e = m.num_nodes(), nt = m.num_tets();
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) c += m.node(m.tets(t, k)) / 4;
  m.nodes.conservativeResize(e + 1, 3);
  m.nodes.row(e) = c.transpose();
  const Eigen::RowVector4i v = m.tets.row(t);
  m.tets.conservativeResize(nt + 3, 4);
  for (int k = 0; k < 4; ++k) {
    Eigen::RowVector4i child = v;
    child(k) = e;
    m.tets.row(k == 0 ? t : nt + k - 1) = child;
  }
  if (m.labels.size() == nt) {
    m.labels.conservativeResize(nt + 3);
    m.labels.tail(3).setConstant(m.labels(t));
  }
}

// Six rigid motions (3 nnode x 6) of nodes at `x` (nnode x 3): three
// translations and three infinitesimal rotations about the centroid.
inline Eigen::MatrixXd rigid_motions(const Eigen::MatrixX3d& x) {
  const Eigen::RowVector3d c = x.colwise().mean();
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(3 * x.rows(), 6);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const Eigen::Vector3d p = (x.row(i) - c).transpose();
    for (int a = 0; a < 3; ++a) {
      R(3 * i + a, a) = 1;
      Eigen::Vector3d axis = Eigen::Vector3d::Unit(a);
      R.block<3, 1>(3 * i, 3 + a) = axis.cross(p);
    }
  }
  return R;
}

// Boxes [0,1]^3 shifted by `shifts`, nodes at equal positions merged: boxes
// that touch share a face, an edge or a node.
inline mesh::TetMesh touching_boxes(const std::vector<Eigen::Vector3d>& shifts) {
  const mesh::TetMesh a = test::jittered_box(2, 2, 2, 0, 1);
  std::vector<Eigen::Vector3d> pos;
  std::vector<std::array<int, 4>> tets;
  auto id_of = [&](const Eigen::Vector3d& x) {
    for (size_t k = 0; k < pos.size(); ++k)
      if ((pos[k] - x).norm() < 1e-12) return int(k);
    pos.push_back(x);
    return int(pos.size() - 1);
  };
  for (const Eigen::Vector3d& d : shifts)
    for (int t = 0; t < a.num_tets(); ++t) {
      std::array<int, 4> q;
      for (int k = 0; k < 4; ++k) q[size_t(k)] = id_of(a.node(a.tets(t, k)) + d);
      tets.push_back(q);
    }
  mesh::TetMesh m;
  m.nodes.resize(Eigen::Index(pos.size()), 3);
  for (size_t k = 0; k < pos.size(); ++k) m.nodes.row(Eigen::Index(k)) = pos[k].transpose();
  m.tets.resize(Eigen::Index(tets.size()), 4);
  for (size_t t = 0; t < tets.size(); ++t)
    for (int k = 0; k < 4; ++k) m.tets(Eigen::Index(t), k) = tets[t][size_t(k)];
  m.labels = Eigen::VectorXi::Zero(m.num_tets());
  return m;
}

}  // namespace softcut::test
