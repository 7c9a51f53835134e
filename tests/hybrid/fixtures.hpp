#pragma once
// Random meshes, partitions, fixed sets and loads for the hybrid suites.
#include <Eigen/Core>
#include <random>
#include <vector>

#include "fem/material.hpp"
#include "hybrid/loads.hpp"
#include "hybrid/partition.hpp"
#include "mesh/generate/box.hpp"

namespace softcut::test {

struct HybridCase {
  mesh::TetMesh mesh;
  std::vector<fem::Material> material;  // (ntet)
  std::vector<int> fixed;               // fixed node ids
  std::vector<char> fixed_mask;         // (nnode)
  hybrid::Partition partition;
  int partition_kind = 0;               // 0 sphere, 1 box, 2 half-space, 3 tet list, 4 empty, 5 whole body
};

inline mesh::TetMesh random_box(std::mt19937& rng, int max_cells = 4) {
  std::uniform_int_distribution<int> cells(1, max_cells);
  std::uniform_real_distribution<double> len(0.5, 2.0);
  mesh::BoxOptions o;
  o.nx = cells(rng) + 1;
  o.ny = cells(rng);
  o.nz = cells(rng);
  o.max_corner = Eigen::Vector3d(len(rng), len(rng), len(rng)) * 0.05;
  o.jitter = 0.2;
  o.seed = unsigned(rng());
  return mesh::generate_box(o);
}

inline std::vector<char> random_operational_mask(const mesh::TetMesh& m, int kind, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  const Eigen::Vector3d lo = m.nodes.colwise().minCoeff(), hi = m.nodes.colwise().maxCoeff();
  auto point = [&] { return Eigen::Vector3d(lo + (hi - lo).cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)))); };
  switch (kind) {
    case 0: return hybrid::tets_in_sphere(m, point(), (0.2 + 0.4 * u(rng)) * (hi - lo).norm());
    case 1: {
      const Eigen::Vector3d a = point(), b = point();
      return hybrid::tets_in_box(m, a.cwiseMin(b), a.cwiseMax(b));
    }
    case 2: return hybrid::tets_in_half_space(m, point(), Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
    case 3: {
      std::vector<int> ids;
      const double frac = 0.1 + 0.4 * u(rng);
      for (int t = 0; t < m.num_tets(); ++t)
        if (u(rng) < frac) ids.push_back(t);
      return hybrid::tets_from_list(m, ids);
    }
    case 4: return std::vector<char>(size_t(m.num_tets()), 0);
    default: return std::vector<char>(size_t(m.num_tets()), 1);
  }
}

// Fixed: the nodes of the face x = min (keeps K nonsingular) plus a few
// random nodes anywhere, so both regions usually hold fixed nodes.
inline HybridCase random_case(std::mt19937& rng, int kind = -1, int max_cells = 4) {
  HybridCase c;
  c.mesh = random_box(rng, max_cells);
  std::uniform_real_distribution<double> u(0, 1);
  for (int t = 0; t < c.mesh.num_tets(); ++t)
    c.material.push_back({2e3 * (1 + 9 * u(rng)), 0.25 + 0.2 * u(rng)});
  const double x0 = c.mesh.nodes.col(0).minCoeff();
  c.fixed_mask.assign(size_t(c.mesh.num_nodes()), 0);
  for (int v = 0; v < c.mesh.num_nodes(); ++v)
    if (c.mesh.nodes(v, 0) == x0 || u(rng) < 0.05) {
      c.fixed.push_back(v);
      c.fixed_mask[size_t(v)] = 1;
    }
  c.partition_kind = kind >= 0 ? kind : int(rng() % 6);
  c.partition = hybrid::make_partition(c.mesh, random_operational_mask(c.mesh, c.partition_kind, rng), c.fixed);
  return c;
}

// A case large enough for CHOLMOD's supernodal K22 (the random cases are
// simplicial): a unit box of nx x 8 x 8 cells, jittered, the face x = 0
// fixed, the tets within 0.3 of the top face's middle operational.
inline HybridCase supernodal_case(int nx, const fem::Material& material) {
  HybridCase c;
  mesh::BoxOptions o;
  o.nx = nx, o.ny = 8, o.nz = 8;
  o.jitter = 0.1;
  c.mesh = mesh::generate_box(o);
  c.material.assign(size_t(c.mesh.num_tets()), material);
  c.fixed_mask.assign(size_t(c.mesh.num_nodes()), 0);
  for (int v = 0; v < c.mesh.num_nodes(); ++v)
    if (c.mesh.nodes(v, 0) == 0) c.fixed.push_back(v), c.fixed_mask[size_t(v)] = 1;
  c.partition = hybrid::make_partition(c.mesh, hybrid::tets_in_sphere(c.mesh, Eigen::Vector3d(0.5, 0.5, 1.0), 0.3), c.fixed);
  return c;
}

// Random loads on nodes of sets 1, I and s (up to `count`), forces ~ N(0, 1) N.
inline std::vector<hybrid::Load> random_loads(const hybrid::Partition& p, std::mt19937& rng, int count) {
  std::vector<int> candidates;
  for (const auto* set : {&p.operational, &p.interface, &p.surface}) candidates.insert(candidates.end(), set->begin(), set->end());
  std::vector<hybrid::Load> loads;
  if (candidates.empty()) return loads;
  std::normal_distribution<double> g(0, 1);
  for (int k = 0; k < count; ++k)
    loads.push_back({candidates[rng() % candidates.size()], Eigen::Vector3d(g(rng), g(rng), g(rng))});
  return loads;
}

inline Eigen::MatrixX3d load_field(int nnode, const std::vector<hybrid::Load>& loads) {
  Eigen::MatrixX3d f = Eigen::MatrixX3d::Zero(nnode, 3);
  for (const auto& l : loads) f.row(l.node) += l.force.transpose();
  return f;
}

// max |a - b| over the rows of `nodes` divided by max |b| over all rows.
inline double relative_error(const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b, const std::vector<int>& nodes) {
  double err = 0;
  for (int v : nodes) err = std::max(err, (a.row(v) - b.row(v)).cwiseAbs().maxCoeff());
  const double scale = b.cwiseAbs().maxCoeff();
  return scale > 0 ? err / scale : err;
}

}  // namespace softcut::test
