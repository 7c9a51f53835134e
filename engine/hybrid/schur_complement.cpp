#include "hybrid/schur_complement.hpp"

#include <cholmod.h>

#include <algorithm>
#include <vector>

#include "core/error.hpp"
#include "core/signal_actions.hpp"

namespace softcut::hybrid {

namespace {

// Lower triangle of a compressed column-major matrix as a CHOLMOD view (no copy).
cholmod_sparse lower_view(SparseMatrix& A) {
  cholmod_sparse v{};
  v.nrow = size_t(A.rows());
  v.ncol = size_t(A.cols());
  v.nzmax = size_t(A.nonZeros());
  v.p = A.outerIndexPtr();
  v.i = A.innerIndexPtr();
  v.x = A.valuePtr();
  v.stype = -1;
  v.itype = CHOLMOD_INT;
  v.xtype = CHOLMOD_REAL;
  v.dtype = CHOLMOD_DOUBLE;
  v.sorted = 1;
  v.packed = 1;
  return v;
}

struct Common {
  cholmod_common c;
  Common() {
    cholmod_start(&c);
    c.print = 0;
  }
  ~Common() { cholmod_finish(&c); }
};

}  // namespace

Eigen::MatrixXd schur_complement(const SparseMatrix& A22_in, const SparseMatrix& A2I, const Eigen::MatrixXd& AII,
                                 const std::string& what) {
  const int n2 = int(A22_in.rows()), ni = int(AII.rows()), n = n2 + ni;
  if (ni == 0) return AII;
  if (A2I.rows() != n2 || A2I.cols() != ni || AII.cols() != ni)
    fail(what, ": Schur complement blocks do not fit (", n2, ", ", A2I.rows(), "x", A2I.cols(), ", ", ni, ")");
  if (n2 == 0) return AII;

  Common cm;
  // Fill-reducing ordering of A22 alone; the I block is appended unpermuted.
  SparseMatrix A22 = A22_in.triangularView<Eigen::Lower>();
  A22.makeCompressed();
  std::vector<int> perm(static_cast<size_t>(n));
  {
    cholmod_sparse v = lower_view(A22);
    const KeepSignalActions keep;  // METIS's ordering re-installs SIGTERM's handler
    cholmod_factor* L22 = cholmod_analyze(&v, &cm.c);
    if (!L22) fail(what, ": CHOLMOD could not order the matrix (status ", cm.c.status, ")");
    const int* p = static_cast<const int*>(L22->Perm);
    for (int k = 0; k < n2; ++k) perm[size_t(k)] = p[k];
    cholmod_free_factor(&L22, &cm.c);
  }
  for (int k = n2; k < n; ++k) perm[size_t(k)] = k;

  // Lower triangle of the bordered matrix [A22 A2I; AI2 AII].
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(size_t(A22.nonZeros() + A2I.nonZeros()) + size_t(ni) * size_t(ni + 1) / 2);
  for (int j = 0; j < n2; ++j)
    for (SparseMatrix::InnerIterator it(A22, j); it; ++it) trip.emplace_back(int(it.row()), j, it.value());
  for (int k = 0; k < ni; ++k)
    for (SparseMatrix::InnerIterator it(A2I, k); it; ++it) trip.emplace_back(n2 + k, int(it.row()), it.value());
  // The bordered matrix is only semidefinite when the region floats apart from
  // the I block (K^non of a region without its own fixed nodes), while S is
  // still well defined: factor with AII + sigma I, whose Schur complement is
  // S + sigma I, and take sigma back off.
  const double sigma = std::max(AII.diagonal().cwiseAbs().maxCoeff(), 1e-300);
  for (int k = 0; k < ni; ++k)
    for (int i = k; i < ni; ++i) trip.emplace_back(n2 + i, n2 + k, AII(i, k) + (i == k ? sigma : 0.0));
  SparseMatrix A(n, n);
  A.setFromTriplets(trip.begin(), trip.end());
  A.makeCompressed();
  cholmod_sparse v = lower_view(A);

  cm.c.nmethods = 1;
  cm.c.method[0].ordering = CHOLMOD_GIVEN;
  cm.c.postorder = 0;
  cholmod_factor* L = cholmod_analyze_p(&v, perm.data(), nullptr, 0, &cm.c);
  if (!L) fail(what, ": CHOLMOD analysis failed (status ", cm.c.status, ")");
  cholmod_factorize(&v, L, &cm.c);
  const bool ok = cm.c.status == CHOLMOD_OK && L->minor == size_t(n);
  bool ordered = true;
  for (int k = n2; k < n && ok; ++k) ordered &= static_cast<const int*>(L->Perm)[k] == k;
  if (ok && ordered) cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, L, &cm.c);  // simplicial LL^T, packed
  if (!ok || !ordered || L->is_super || !L->is_ll) {
    cholmod_free_factor(&L, &cm.c);
    if (!ok)
      fail(what, ": the stiffness matrix is singular or not positive definite; every connected part of the body "
                 "needs fixed nodes");
    fail(what, ": CHOLMOD did not keep the interface block last (internal error)");
  }
  // Trailing block of L (columns and rows n2..n-1, unpermuted).
  Eigen::MatrixXd LII = Eigen::MatrixXd::Zero(ni, ni);
  const int* Lp = static_cast<const int*>(L->p);
  const int* Li = static_cast<const int*>(L->i);
  const int* Lnz = static_cast<const int*>(L->nz);
  const double* Lx = static_cast<const double*>(L->x);
  for (int j = n2; j < n; ++j)
    for (int q = Lp[j]; q < Lp[j] + Lnz[j]; ++q)
      if (Li[q] >= n2) LII(Li[q] - n2, j - n2) = Lx[q];
  cholmod_free_factor(&L, &cm.c);
  Eigen::MatrixXd S(ni, ni);
  S.setZero();
  S.selfadjointView<Eigen::Lower>().rankUpdate(LII);
  S.triangularView<Eigen::StrictlyUpper>() = S.transpose();
  S.diagonal().array() -= sigma;
  return S;
}

}  // namespace softcut::hybrid
