#include "fem/assembly.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <numeric>
#include <thread>

#include "core/error.hpp"
#include "core/threads.hpp"
#include "fem/element_stiffness.hpp"

namespace softcut::fem {

namespace {

// The tet list an assembler works on: `tets_in`, or every tet when empty.
std::vector<int> tet_set(const mesh::TetMesh& m, const std::vector<int>& tets_in) {
  if (!tets_in.empty()) return tets_in;
  std::vector<int> all(static_cast<size_t>(m.num_tets()));
  std::iota(all.begin(), all.end(), 0);
  return all;
}

}  // namespace

void check_tets(const mesh::TetMesh& m, const std::vector<Material>& tet_material, const std::vector<int>& tets,
                const char* who) {
  const int nn = m.num_nodes(), nt = m.num_tets();
  if (int(tet_material.size()) != nt)
    fail(who, ": ", tet_material.size(), " materials for ", nt, " tetrahedra; give one material per tet");
  for (int t : tets) {
    if (t < 0 || t >= nt) fail(who, ": tet id ", t, " in the tet list is out of range 0..", nt - 1);
    for (int k = 0; k < 4; ++k)
      if (m.tets(t, k) < 0 || m.tets(t, k) >= nn)
        fail(who, ": tetrahedron ", t, " refers to node ", m.tets(t, k), ", but the mesh has nodes 0..", nn - 1);
    const Material& mat = tet_material[size_t(t)];
    bool strain_ok = true;  // the message is built only for a bad material
    for (int k = 0; k < 6; ++k)
      strain_ok = strain_ok && std::abs(mat.initial_strain[size_t(k)]) <= (k < 3 ? 1 : 2) * kMaxInitialStrain;
    if (!(std::isfinite(mat.young) && mat.young > 0 && mat.poisson > -1.0 && mat.poisson < 0.5) || !strain_ok)
      check_material(mat, cat(who, ": material of tetrahedron ", t));
    const TetCorners X = tet_corners(m, t);
    double l = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) l = std::max(l, (X.row(i) - X.row(j)).norm());
    const double V = mesh::signed_volume(X.row(0).transpose(), X.row(1).transpose(), X.row(2).transpose(),
                                         X.row(3).transpose());
    if (!(V > mesh::kDegenerateVolume * l * l * l))
      fail(who, ": tetrahedron ", t, " (nodes ", m.tets(t, 0), " ", m.tets(t, 1), " ", m.tets(t, 2), " ",
           m.tets(t, 3), ") has volume ", V, " m^3 for longest edge ", l,
           " m: it is inverted or degenerate; run mesh::validate (which reorients) or fix its nodes");
  }
}

SparseMatrix assemble_stiffness(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                const std::vector<int>& tets_in, int threads, const StopFlags* stop) {
  const int nn = m.num_nodes();
  const std::vector<int> tets = tet_set(m, tets_in);
  check_tets(m, tet_material, tets, "assemble_stiffness");

  // Node adjacency per column node: sorted unique neighbours (incl. itself).
  std::vector<int> count(size_t(nn) + 1, 0);
  for (int t : tets)
    for (int b = 0; b < 4; ++b) count[size_t(m.tets(t, b)) + 1] += 4;
  std::partial_sum(count.begin(), count.end(), count.begin());
  std::vector<int> nbr(size_t(count.back()));
  {
    std::vector<int> fill(count.begin(), count.end() - 1);
    for (int t : tets)
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
  if (nnz > Eigen::Index(std::numeric_limits<int>::max()))
    fail("assemble_stiffness: ", nnz, " nonzeros exceed the 32-bit index range of the sparse matrix");
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

  // Adds the columns of tet t whose node lies in [lo, hi).
  auto scatter = [&](int t, int lo, int hi) {
    const Mat12 Ke = element_stiffness(tet_corners(m, t), tet_material[size_t(t)]);
    for (int b = 0; b < 4; ++b) {
      const int j = m.tets(t, b);
      if (j < lo || j >= hi) continue;
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
  };

  int nthreads = threads;
  if (nthreads <= 0)
    nthreads = tets.size() < 20000 ? 1 : int(std::clamp(std::thread::hardware_concurrency(), 1u, 8u));
  // ~10 ms of elements between polls.
  constexpr size_t kPollEvery = 8192;
  if (nthreads == 1) {
    for (size_t k = 0; k < tets.size(); ++k) {
      if (stop && k % kPollEvery == 0) stop->poll("assembling the stiffness matrix");
      scatter(tets[k], 0, nn);
    }
    return K;
  }

  // Owner computes: node ranges with equal incidence counts; each thread walks
  // the tets touching its range in tet order (so every entry receives its
  // contributions in the same order as the serial loop) and writes only its
  // own columns. Tets straddling two ranges are computed by both owners.
  std::vector<int> bound(size_t(nthreads) + 1, nn);
  bound[0] = 0;
  for (int p = 1; p < nthreads; ++p) {
    const int target = int(int64_t(count.back()) * p / nthreads);
    bound[size_t(p)] = int(std::lower_bound(count.begin(), count.end() - 1, target) - count.begin());
  }
  std::vector<int> owner(static_cast<size_t>(nn));
  for (int p = 0; p < nthreads; ++p)
    for (int j = bound[size_t(p)]; j < bound[size_t(p) + 1]; ++j) owner[size_t(j)] = p;
  std::vector<std::vector<int>> work(static_cast<size_t>(nthreads));
  for (int t : tets) {
    int seen[4];
    int n = 0;
    for (int b = 0; b < 4; ++b) {
      const int p = owner[size_t(m.tets(t, b))];
      if (std::find(seen, seen + n, p) == seen + n) {
        seen[n++] = p;
        work[size_t(p)].push_back(t);
      }
    }
  }
  std::vector<std::thread> pool;
  for (int p = 0; p < nthreads; ++p)
    pool.emplace_back([&, p] {
      const std::vector<int>& mine = work[size_t(p)];
      for (size_t k = 0; k < mine.size(); ++k) {
        if (stop && k % kPollEvery == 0 && stop->requested()) return;  // thrown below, on the caller's thread
        scatter(mine[k], bound[size_t(p)], bound[size_t(p) + 1]);
      }
    });
  for (auto& th : pool) th.join();
  if (stop) stop->poll("assembling the stiffness matrix");
  return K;
}

BlockStiffness assemble_node_blocks(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                    const std::vector<int>& tets_in, const std::vector<int>& position,
                                    int num_positions, int threads) {
  const int nn = m.num_nodes();
  if (int(position.size()) != nn)
    fail("assemble_node_blocks: ", position.size(), " node positions for a mesh of ", nn, " nodes");
  for (int p : position)
    if (p < -1 || p >= num_positions)
      fail("assemble_node_blocks: node position ", p, " outside -1..", num_positions - 1);
  const std::vector<int> tets = tet_set(m, tets_in);
  check_tets(m, tet_material, tets, "assemble_node_blocks");
  auto pos = [&](int t, int b) { return position[size_t(m.tets(t, b))]; };

  // Node rows: sorted unique neighbours in the subset (incl. itself).
  BlockStiffness K;
  std::vector<int> count(size_t(num_positions) + 1, 0);
  for (int t : tets)
    for (int b = 0; b < 4; ++b)
      if (pos(t, b) >= 0) count[size_t(pos(t, b)) + 1] += 4;
  std::partial_sum(count.begin(), count.end(), count.begin());
  std::vector<int> nbr(size_t(count.back()));
  std::vector<int> fill(count.begin(), count.end() - 1), end(fill);
  for (int t : tets)
    for (int b = 0; b < 4; ++b)
      if (pos(t, b) >= 0)
        for (int a = 0; a < 4; ++a)
          if (pos(t, a) >= 0) nbr[size_t(end[size_t(pos(t, b))]++)] = pos(t, a);
  K.row_start.assign(1, 0);
  for (int j = 0; j < num_positions; ++j) {
    auto b = nbr.begin() + fill[size_t(j)], e = nbr.begin() + end[size_t(j)];
    std::sort(b, e);
    K.col.insert(K.col.end(), b, std::unique(b, e));
    K.row_start.push_back(int(K.col.size()));
  }
  K.blocks.assign(K.col.size(), Eigen::Matrix3d::Zero());

  // Adds tet t into the node rows in [lo, hi).
  auto scatter = [&](int t, int lo, int hi) {
    const Mat12 Ke = element_stiffness(tet_corners(m, t), tet_material[size_t(t)]);
    const std::array<int, 4> p{pos(t, 0), pos(t, 1), pos(t, 2), pos(t, 3)};
    for (int b = 0; b < 4; ++b)
      if (p[size_t(b)] >= lo && p[size_t(b)] < hi) add_element_row(K, Ke, p, b);
  };
  // Owner computes, as assemble_stiffness: two row ranges of equal block
  // counts, each thread walking the tets that touch its range in tet order
  // (same additions in the same order per entry, whatever the threads).
  const int nthreads = threads > 0 ? std::min(threads, 2) : tets.size() >= 2000 ? std::min(2, thread_policy().threads) : 1;
  auto range = [&](int lo, int hi) {
    for (int t : tets)
      for (int b = 0; b < 4; ++b)
        if (pos(t, b) >= lo && pos(t, b) < hi) {
          scatter(t, lo, hi);
          break;
        }
  };
  if (nthreads == 1 || num_positions < 2) {
    range(0, num_positions);
    return K;
  }
  const int split = int(std::lower_bound(K.row_start.begin(), K.row_start.end(), int(K.col.size() / 2)) -
                        K.row_start.begin());
  std::exception_ptr error;  // check_tets ran: nothing should throw, but never across a thread
  std::thread second([&] {
    try {
      range(split, num_positions);
    } catch (...) {
      error = std::current_exception();
    }
  });
  range(0, split);
  second.join();
  if (error) std::rethrow_exception(error);
  return K;
}

void add_element_row(BlockStiffness& K, const Mat12& Ke, const std::array<int, 4>& pos, int b) {
  const int j = pos[size_t(b)];
  const int* first = K.col.data() + K.row_start[size_t(j)];
  const int* last = K.col.data() + K.row_start[size_t(j) + 1];
  for (int a = 0; a < 4; ++a) {
    if (pos[size_t(a)] < 0) continue;
    Eigen::Matrix3d& B = K.blocks[size_t(std::lower_bound(first, last, pos[size_t(a)]) - K.col.data())];
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) B(c, r) += Ke(3 * a + r, 3 * b + c);  // K(3 i + r, 3 j + c) as assembled
  }
}

SparseMatrix BlockStiffness::to_sparse() const {
  const int n = nodes();
  SparseMatrix K(3 * Eigen::Index(n), 3 * Eigen::Index(n));
  K.resizeNonZeros(9 * Eigen::Index(col.size()));
  int* outer = K.outerIndexPtr();
  int* inner = K.innerIndexPtr();
  double* val = K.valuePtr();
  for (int j = 0; j < n; ++j) {
    const int first = row_start[size_t(j)], deg = row_start[size_t(j) + 1] - first;
    for (int c = 0; c < 3; ++c) {
      const int off = 9 * first + 3 * c * deg;
      outer[3 * j + c] = off;
      for (int k = 0; k < deg; ++k)
        for (int r = 0; r < 3; ++r) {
          inner[off + 3 * k + r] = 3 * col[size_t(first + k)] + r;
          val[off + 3 * k + r] = blocks[size_t(first + k)](c, r);  // column 3j+c, row 3i+r (symmetric)
        }
    }
  }
  outer[3 * n] = 9 * int(col.size());
  return K;
}

SparseMatrix assemble_stiffness_triplets(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                                         const std::vector<int>& tets_in) {
  const int nn = m.num_nodes();
  const std::vector<int> tets = tet_set(m, tets_in);
  check_tets(m, tet_material, tets, "assemble_stiffness_triplets");
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(144 * tets.size());
  for (int t : tets) {
    const Mat12 Ke = element_stiffness(tet_corners(m, t), tet_material[size_t(t)]);
    for (int b = 0; b < 4; ++b)
      for (int c = 0; c < 3; ++c)
        for (int a = 0; a < 4; ++a)
          for (int r = 0; r < 3; ++r)
            trip.emplace_back(3 * m.tets(t, a) + r, 3 * m.tets(t, b) + c, Ke(3 * a + r, 3 * b + c));
  }
  SparseMatrix K(3 * nn, 3 * nn);
  K.setFromTriplets(trip.begin(), trip.end());
  return K;
}

Eigen::MatrixX3d element_loads(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                               const std::vector<int>& tets_in) {
  const std::vector<int> tets = tet_set(m, tets_in);
  check_tets(m, tet_material, tets, "element_loads");
  Eigen::MatrixX3d f = Eigen::MatrixX3d::Zero(m.num_nodes(), 3);
  for (int t : tets) {
    const Material& mat = tet_material[size_t(t)];
    const bool strained = has_initial_strain(mat), weighed = has_body_force(mat);
    if (!strained && !weighed) continue;
    double V = 0;
    const Mat6x12 B = strain_displacement(tet_corners(m, t), &V);
    if (strained) {
      const Eigen::Matrix<double, 6, 1> eps0 = Eigen::Map<const Eigen::Matrix<double, 6, 1>>(mat.initial_strain.data());
      const Eigen::Matrix<double, 12, 1> fe = V * (B.transpose() * (elasticity_matrix(mat) * eps0));
      for (int k = 0; k < 4; ++k) f.row(m.tets(t, k)) += fe.segment<3>(3 * k).transpose();
    }
    if (weighed) {  // a dead load: a quarter of V b on each corner
      const Eigen::RowVector3d share = V / 4 * Eigen::RowVector3d(mat.body_force[0], mat.body_force[1], mat.body_force[2]);
      for (int k = 0; k < 4; ++k) f.row(m.tets(t, k)) += share;
    }
  }
  return f;
}

bool any_element_load(const std::vector<Material>& tet_material) {
  for (const Material& mat : tet_material)
    if (has_initial_strain(mat) || has_body_force(mat)) return true;
  return false;
}

double strain_energy(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                     const Eigen::MatrixX3d& u) {
  if (u.rows() != m.num_nodes())
    fail("strain_energy: displacement field has ", u.rows(), " rows for ", m.num_nodes(), " nodes");
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
