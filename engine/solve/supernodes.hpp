#pragma once
// The solve stage's view of CHOLMOD's factors (internal to engine/solve/):
// Eigen's decomposition with access to its cholmod_factor, the supernodal
// factor as arrays, and the pieces the supernode-by-supernode solves share
// (solve/supernodal_solves.cpp, solve/cholesky_io.cpp's layout check).
#include <Eigen/CholmodSupport>
#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "solve/cholesky.hpp"

namespace softcut::solve {

class Cholesky::Llt : public Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  cholmod_factor* raw() const { return m_cholmodFactor; }
  // Takes ownership of a numeric factor made outside Eigen (load()).
  void adopt(cholmod_factor* L) {
    if (m_cholmodFactor) cholmod_free_factor(&m_cholmodFactor, &cholmod());
    m_cholmodFactor = L;
    m_isInitialized = true;
    m_info = Eigen::Success;
    m_analysisIsOk = true;
    m_factorizationIsOk = true;
  }
};

// A cholmod_dense header over Eigen's column-major data (no copy).
inline cholmod_dense dense_view(const double* data, Eigen::Index rows, Eigen::Index cols) {
  cholmod_dense d{};
  d.nrow = size_t(rows);
  d.ncol = size_t(cols);
  d.nzmax = d.nrow * d.ncol;
  d.d = d.nrow;
  d.x = const_cast<double*>(data);  // read only (CHOLMOD's API is not const)
  d.xtype = CHOLMOD_REAL;
  d.dtype = CHOLMOD_DOUBLE;
  return d;
}
// CHOLMOD's supernodal factor (int, real LL') as arrays. Supernode s holds
// columns super[s] .. super[s+1]-1 of L; its rows are Ls[pi[s] ..] (its own
// columns first, then increasing), its values a rows(s) x cols(s)
// column-major block at Lx[px[s]]. The parent of s is the supernode of its
// first row below the diagonal block; parents come after children.
struct Supernodes {
  explicit Supernodes(const cholmod_factor& L)
      : super(static_cast<const int*>(L.super)), pi(static_cast<const int*>(L.pi)),
        px(static_cast<const int*>(L.px)), Ls(static_cast<const int*>(L.s)), Lx(static_cast<const double*>(L.x)),
        count(int(L.nsuper)) {}
  const int *super, *pi, *px, *Ls;
  const double* Lx;
  int count;
  int cols(int s) const { return super[s + 1] - super[s]; }
  int rows(int s) const { return pi[s + 1] - pi[s]; }
  Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> block(int s) const {
    return {Lx + px[s], rows(s), cols(s), Eigen::OuterStride<>(rows(s))};
  }
  // The supernode holding column `col`.
  int of(int col) const { return int(std::upper_bound(super, super + count + 1, col) - super) - 1; }
  // The parent of s, -1 for a root (no rows below its diagonal block).
  int parent(int s) const { return rows(s) > cols(s) ? of(Ls[pi[s] + cols(s)]) : -1; }
};

// The one-vector solves take the last supernode in blocks of kSplitTop when
// it is a dense top (no rows below its columns) of that many columns or more.
inline bool splits_top(const Supernodes& sn) {
  const int top = sn.count - 1;
  return sn.rows(top) == sn.cols(top) && sn.cols(top) >= Cholesky::kSplitTop;
}

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The backward solve's step at supernode s: V = its rows of T, its own
// columns' first (still to finish), then the rows below them (final: they
// belong to ancestors). Column c of the block, read once from memory,
// finishes V's row c; the finished rows go back to T.
void backward_supernode(const Supernodes& sn, int s, RowMajorMatrix& T, Eigen::MatrixXd& V,
                        std::vector<double>& sum);

// How a backward solve shares the supernodes out between two threads:
// item[s] = 0 for the top of the elimination tree (solved first, on the
// caller), k >= 1 for the whole subtrees below it, item k-1 of a job the
// two threads claim from (HelperThread::run_items), largest first. The top
// grows from the roots, the heaviest subtree split first, until no subtree
// holds more than an eighth of the entries of L read (in a nested
// dissection tree: a few levels of separators down) or the top a quarter.
std::vector<int> subtree_items(const Supernodes& sn);

}  // namespace softcut::solve
