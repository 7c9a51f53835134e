#include "mesh/generate/box.hpp"

#include <random>

#include "core/error.hpp"
#include "mesh/generate/extrude.hpp"

namespace softcut::mesh {

MeshSize box_size(const BoxOptions& o) {
  return {(o.nx + 1.0) * (o.ny + 1.0) * (o.nz + 1.0), 6.0 * o.nx * o.ny * o.nz};
}

TetMesh generate_box(const BoxOptions& o) {
  if (o.nx < 1 || o.ny < 1 || o.nz < 1) fail("box: cell counts must be >= 1, got ", o.nx, " ", o.ny, " ", o.nz);
  if (!((o.max_corner - o.min_corner).minCoeff() > 0)) fail("box: max corner must exceed min corner on every axis");
  if (!(o.jitter >= 0 && o.jitter < 0.25)) fail("box: jitter must lie in [0, 0.25), got ", o.jitter);
  check_mesh_size("box", box_size(o));
  const int px = o.nx + 1, py = o.ny + 1, pz = o.nz + 1;
  const Eigen::Vector3d h = (o.max_corner - o.min_corner).cwiseQuotient(Eigen::Vector3d(o.nx, o.ny, o.nz));
  TetMesh m;
  m.nodes.resize(px * py * pz, 3);
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto id = [&](int i, int j, int k) { return i + px * (j + py * k); };
  for (int k = 0; k < pz; ++k)
    for (int j = 0; j < py; ++j)
      for (int i = 0; i < px; ++i) {
        Eigen::Vector3d p = o.min_corner + Eigen::Vector3d(i, j, k).cwiseProduct(h);
        const bool interior = i > 0 && i < o.nx && j > 0 && j < o.ny && k > 0 && k < o.nz;
        if (o.jitter > 0 && interior)
          for (int c = 0; c < 3; ++c) p(c) += o.jitter * h(c) * u(rng);
        m.nodes.row(id(i, j, k)) = p.transpose();
      }
  // Kuhn split: the six monotone lattice paths from corner 000 to 111.
  static constexpr int kPaths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  m.tets.resize(6 * o.nx * o.ny * o.nz, 4);
  int t = 0;
  for (int k = 0; k < o.nz; ++k)
    for (int j = 0; j < o.ny; ++j)
      for (int i = 0; i < o.nx; ++i)
        for (const auto& path : kPaths) {
          int c[3] = {i, j, k};
          m.tets(t, 0) = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[path[s]];
            m.tets(t, s + 1) = id(c[0], c[1], c[2]);
          }
          if (signed_volume(m, t) < 0) std::swap(m.tets(t, 2), m.tets(t, 3));
          ++t;
        }
  m.labels = Eigen::VectorXi::Constant(m.num_tets(), o.label);
  return m;
}

}  // namespace softcut::mesh
