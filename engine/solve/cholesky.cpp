#include "solve/cholesky.hpp"

#include "core/error.hpp"

namespace softcut::solve {

class Cholesky::Llt : public Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  cholmod_factor* raw() const { return m_cholmodFactor; }
};

SolveWorkspace::SolveWorkspace() {
  cholmod_start(&c_);
  c_.print = 0;
}

SolveWorkspace::~SolveWorkspace() { cholmod_finish(&c_); }

Cholesky::Cholesky(const Eigen::SparseMatrix<double>& A, const std::string& what) { factor(A, what); }

void Cholesky::factor(const Eigen::SparseMatrix<double>& A, const std::string& what, double max_bytes) {
  if (A.rows() != A.cols()) fail(what, ": Cholesky needs a square matrix, got ", A.rows(), "x", A.cols());
  llt_.reset();  // a failed factor() leaves the object unfactored, not holding a stale factor
  rows_ = 0;
  lnz_ = 0;
  auto llt = std::make_shared<Llt>();
  llt->cholmod().print = 0;  // CHOLMOD must not print; failures become softcut::Error
  // Eigen's default (final_asis) keeps CHOLMOD's simplicial LDL' for small
  // matrices, which factors indefinite matrices without complaint; asking for
  // a final LL' makes every non-positive pivot an error, in both the
  // simplicial and the supernodal path (tested).
  llt->cholmod().final_asis = 0;
  llt->cholmod().final_ll = 1;
  llt->analyzePattern(A);
  // The factor's nonzeros are known after the symbolic analysis: 8 bytes of
  // value and 4-8 of index each (supernodal storage pads a little more).
  const double bytes = 16.0 * llt->cholmod().lnz;
  if (bytes > max_bytes)
    fail(what, ": its Cholesky factor would take about ", int(bytes / (1 << 20)), " MiB (", A.rows(),
         " unknowns), more than the ", int(max_bytes / (1 << 20)), " MiB allowed (the sandbox's memory budget); "
         "use a coarser mesh or run with --trust");
  llt->factorize(A);
  if (llt->info() != Eigen::Success)
    fail(what, ": the stiffness matrix is singular or not positive definite; every connected part of "
               "the body needs fixed nodes");
  lnz_ = llt->cholmod().lnz;
  llt_ = std::move(llt);
  rows_ = int(A.rows());
}

Eigen::VectorXd Cholesky::solve(const Eigen::VectorXd& b) const {
  if (!llt_) fail("Cholesky::solve called before factor()");
  if (b.size() != rows_) fail("Cholesky::solve: right-hand side of size ", b.size(), " for a ", rows_, "-row factor");
  return llt_->solve(b);
}

Eigen::MatrixXd Cholesky::solve(const Eigen::MatrixXd& B) const {
  if (!llt_) fail("Cholesky::solve called before factor()");
  if (B.rows() != rows_) fail("Cholesky::solve: right-hand sides with ", B.rows(), " rows for a ", rows_, "-row factor");
  return llt_->solve(B);
}

Eigen::MatrixXd Cholesky::solve(const Eigen::MatrixXd& B, SolveWorkspace& ws) const {
  if (!llt_) fail("Cholesky::solve called before factor()");
  if (B.rows() != rows_) fail("Cholesky::solve: right-hand sides with ", B.rows(), " rows for a ", rows_, "-row factor");
  if (B.cols() == 0) return Eigen::MatrixXd(rows_, 0);
  cholmod_dense b{};
  b.nrow = size_t(B.rows());
  b.ncol = size_t(B.cols());
  b.nzmax = b.nrow * b.ncol;
  b.d = b.nrow;
  b.x = const_cast<double*>(B.data());  // read only (CHOLMOD's API is not const)
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* x = cholmod_solve(CHOLMOD_A, llt_->raw(), &b, &ws.common());
  if (!x) fail("Cholesky::solve: CHOLMOD failed (status ", ws.common().status, "; out of memory?)");
  Eigen::MatrixXd X = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(x->x), B.rows(), B.cols());
  cholmod_free_dense(&x, &ws.common());
  return X;
}

Eigen::MatrixXd Cholesky::solve(const Eigen::SparseMatrix<double>& B) const {
  return solve(Eigen::MatrixXd(B));
}

}  // namespace softcut::solve
