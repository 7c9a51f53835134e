#include "fem/assembly.hpp"

#include <algorithm>
#include <numeric>

#include "core/error.hpp"
#include "fem/element_stiffness.hpp"

namespace softcut::fem {

SparseMatrix assemble_stiffness(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                const std::vector<int>& tets_in) {
  const int nn = m.num_nodes();
  if (int(tet_material.size()) != m.num_tets())
    fail("assemble_stiffness: ", tet_material.size(), " materials for ", m.num_tets(), " tetrahedra");
  std::vector<int> all;
  const std::vector<int>* tets = &tets_in;
  if (tets_in.empty()) {
    all.resize(size_t(m.num_tets()));
    std::iota(all.begin(), all.end(), 0);
    tets = &all;
  }

  // Node adjacency per column node: sorted unique neighbours (incl. itself).
  std::vector<int> count(size_t(nn) + 1, 0);
  for (int t : *tets)
    for (int b = 0; b < 4; ++b) count[size_t(m.tets(t, b)) + 1] += 4;
  std::partial_sum(count.begin(), count.end(), count.begin());
  std::vector<int> nbr(size_t(count.back()));
  {
    std::vector<int> fill(count.begin(), count.end() - 1);
    for (int t : *tets)
      for (int b = 0; b < 4; ++b)
        for (int a = 0; a < 4; ++a) nbr[size_t(fill[size_t(m.tets(t, b))]++)] = m.tets(t, a);
  }
  std::vector<int> start(size_t(nn) + 1, 0);  // compacted neighbour lists
  {
    int w = 0;
    for (int j = 0; j < nn; ++j) {
      auto b = nbr.begin() + count[size_t(j)], e = nbr.begin() + count[size_t(j) + 1];
      std::sort(b, e);
      e = std::unique(b, e);
      start[size_t(j)] = w;
      for (auto it = b; it != e; ++it) nbr[size_t(w++)] = *it;
    }
    start[size_t(nn)] = w;
    nbr.resize(size_t(w));
  }

  // CSC arrays: column 3j+c holds rows 3i+r for each neighbour i of j.
  SparseMatrix K(3 * nn, 3 * nn);
  const Eigen::Index nnz = Eigen::Index(9) * Eigen::Index(nbr.size());
  K.resizeNonZeros(nnz);
  int* outer = K.outerIndexPtr();
  int* inner = K.innerIndexPtr();
  double* val = K.valuePtr();
  for (int j = 0; j < nn; ++j) {
    const int deg = start[size_t(j) + 1] - start[size_t(j)];
    for (int c = 0; c < 3; ++c) {
      const int col = 3 * j + c;
      const int off = 9 * start[size_t(j)] + c * 3 * deg;
      outer[col] = off;
      for (int k = 0; k < deg; ++k)
        for (int r = 0; r < 3; ++r) inner[off + 3 * k + r] = 3 * nbr[size_t(start[size_t(j)] + k)] + r;
    }
  }
  outer[3 * nn] = int(nnz);
  std::fill(val, val + nnz, 0.0);

  for (int t : *tets) {
    const Mat12 Ke = element_stiffness(tet_corners(m, t), tet_material[size_t(t)]);
    for (int b = 0; b < 4; ++b) {
      const int j = m.tets(t, b);
      const int deg = start[size_t(j) + 1] - start[size_t(j)];
      const int* first = nbr.data() + start[size_t(j)];
      for (int a = 0; a < 4; ++a) {
        const int k = int(std::lower_bound(first, first + deg, m.tets(t, a)) - first);
        for (int c = 0; c < 3; ++c) {
          double* dst = val + 9 * start[size_t(j)] + c * 3 * deg + 3 * k;
          for (int r = 0; r < 3; ++r) dst[r] += Ke(3 * a + r, 3 * b + c);
        }
      }
    }
  }
  return K;
}

double strain_energy(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                     const Eigen::MatrixX3d& u) {
  double e = 0;
  for (int t = 0; t < m.num_tets(); ++t) {
    Eigen::Matrix<double, 12, 1> ue;
    for (int k = 0; k < 4; ++k) ue.segment<3>(3 * k) = u.row(m.tets(t, k)).transpose();
    double V = 0;
    const Mat6x12 B = strain_displacement(tet_corners(m, t), &V);
    const Eigen::Matrix<double, 6, 1> eps = B * ue;
    e += 0.5 * V * eps.dot(elasticity_matrix(tet_material[size_t(t)]) * eps);
  }
  return e;
}

}  // namespace softcut::fem
