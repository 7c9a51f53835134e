#include "solve/cholesky.hpp"

#include "core/error.hpp"
#include "core/signal_actions.hpp"
#include "solve/supernodes.hpp"

namespace softcut::solve {

SolveWorkspace::SolveWorkspace() {
  cholmod_start(&c_);
  c_.print = 0;
}

SolveWorkspace::~SolveWorkspace() {
  for (cholmod_dense** d : {&X, &Y, &E})
    if (*d) cholmod_free_dense(d, &c_);
  cholmod_finish(&c_);
}
Cholesky::Cholesky(const Eigen::SparseMatrix<double>& A, const std::string& what) { factor(A, what); }

void Cholesky::factor(const Eigen::SparseMatrix<double>& A, const std::string& what, double max_bytes) {
  if (A.rows() != A.cols()) fail(what, ": Cholesky needs a square matrix, got ", A.rows(), "x", A.cols());
  llt_.reset();  // a failed factor() leaves the object unfactored, not holding a stale factor
  item_.clear();
  items_ = 0;
  rows_ = 0;
  lnz_ = 0;
  flops_ = 0;
  auto llt = std::make_shared<Llt>();
  llt->cholmod().print = 0;  // CHOLMOD must not print; failures become softcut::Error
  // Eigen's default (final_asis) keeps CHOLMOD's simplicial LDL' for small
  // matrices, which factors indefinite matrices without complaint; asking for
  // a final LL' makes every non-positive pivot an error, in both the
  // simplicial and the supernodal path (tested).
  llt->cholmod().final_asis = 0;
  llt->cholmod().final_ll = 1;
  {
    const KeepSignalActions keep;  // METIS's ordering re-installs SIGTERM's handler
    llt->analyzePattern(A);
  }
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
  flops_ = llt->cholmod().fl;
  llt_ = std::move(llt);
  if (llt_->raw()->is_super) set_items();
  rows_ = int(A.rows());
}

double Cholesky::symbolic_nonzeros(const Eigen::SparseMatrix<double>& A) {
  if (A.rows() == 0) return 0;
  Llt llt;
  llt.cholmod().print = 0;
  llt.cholmod().final_asis = 0;  // as factor() asks
  llt.cholmod().final_ll = 1;
  const KeepSignalActions keep;  // METIS's ordering re-installs SIGTERM's handler
  llt.analyzePattern(A);
  return double(llt.cholmod().lnz);
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

void Cholesky::solve_into(const Eigen::VectorXd& b, Eigen::VectorXd& x, SolveWorkspace& ws) const {
  if (!llt_) fail("Cholesky::solve called before factor()");
  if (b.size() != rows_) fail("Cholesky::solve: right-hand side of size ", b.size(), " for a ", rows_, "-row factor");
  cholmod_dense B{};
  B.nrow = size_t(b.size());
  B.ncol = 1;
  B.nzmax = B.d = B.nrow;
  B.x = const_cast<double*>(b.data());  // read only
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  if (!cholmod_solve2(CHOLMOD_A, llt_->raw(), &B, nullptr, &ws.X, nullptr, &ws.Y, &ws.E, &ws.common()))
    fail("Cholesky::solve: CHOLMOD failed (status ", ws.common().status, "; out of memory?)");
  x = Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(ws.X->x), b.size());
}


void Cholesky::forward_into(const Eigen::MatrixXd& B, Eigen::MatrixXd& Y, SolveWorkspace& ws) const {
  if (!llt_) fail("Cholesky::forward called before factor()");
  if (B.rows() != rows_) fail("Cholesky::forward: right-hand sides with ", B.rows(), " rows for a ", rows_, "-row factor");
  if (!llt_->raw()->is_ll) fail("Cholesky::forward: the factor is not LL' (an LDL' factor would need D)");
  const int* perm = static_cast<const int*>(llt_->raw()->Perm);
  Y.resize(B.rows(), B.cols());
  if (B.cols() == 0) return;
  for (Eigen::Index k = 0; k < B.rows(); ++k) Y.row(k) = B.row(perm ? perm[k] : k);
  cholmod_dense in = dense_view(Y.data(), Y.rows(), Y.cols());
  cholmod_dense* out = cholmod_solve(CHOLMOD_L, llt_->raw(), &in, &ws.common());
  if (!out) fail("Cholesky::forward: CHOLMOD failed (status ", ws.common().status, "; out of memory?)");
  Y = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(out->x), B.rows(), B.cols());
  cholmod_free_dense(&out, &ws.common());
}

void Cholesky::backward_into(const Eigen::VectorXd& y, Eigen::VectorXd& x, SolveWorkspace& ws) const {
  if (!llt_) fail("Cholesky::backward called before factor()");
  if (y.size() != rows_) fail("Cholesky::backward: a vector of size ", y.size(), " for a ", rows_, "-row factor");
  if (!llt_->raw()->is_ll) fail("Cholesky::backward: the factor is not LL' (an LDL' factor would need D)");
  cholmod_dense in = dense_view(y.data(), y.size(), 1);
  if (!cholmod_solve2(CHOLMOD_Lt, llt_->raw(), &in, nullptr, &ws.X, nullptr, &ws.Y, &ws.E, &ws.common()))
    fail("Cholesky::backward: CHOLMOD failed (status ", ws.common().status, "; out of memory?)");
  const double* t = static_cast<const double*>(ws.X->x);
  const int* perm = static_cast<const int*>(llt_->raw()->Perm);
  x.resize(y.size());
  for (Eigen::Index k = 0; k < y.size(); ++k) x[perm ? perm[k] : k] = t[k];
}

void Cholesky::set_items() {
  item_ = subtree_items(Supernodes(*llt_->raw()));
  items_ = item_.empty() ? 0 : *std::max_element(item_.begin(), item_.end());
}

bool Cholesky::supernodal() const { return llt_ && llt_->raw()->is_super; }

}  // namespace softcut::solve
