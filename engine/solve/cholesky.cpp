#include "solve/cholesky.hpp"

#include "core/error.hpp"

namespace softcut::solve {

Cholesky::Cholesky(const Eigen::SparseMatrix<double>& A, const std::string& what) { factor(A, what); }

void Cholesky::factor(const Eigen::SparseMatrix<double>& A, const std::string& what) {
  if (A.rows() != A.cols()) fail(what, ": Cholesky needs a square matrix, got ", A.rows(), "x", A.cols());
  auto llt = std::make_unique<Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower>>();
  llt->cholmod().print = 0;  // CHOLMOD must not print; failures become softcut::Error
  llt->compute(A);
  if (llt->info() != Eigen::Success)
    fail(what, ": the stiffness matrix is singular or not positive definite; every connected part of "
               "the body needs fixed nodes");
  llt_ = std::move(llt);
  rows_ = int(A.rows());
}

Eigen::VectorXd Cholesky::solve(const Eigen::VectorXd& b) const {
  if (!llt_) fail("Cholesky::solve called before factor()");
  return llt_->solve(b);
}

Eigen::MatrixXd Cholesky::solve(const Eigen::MatrixXd& B) const {
  if (!llt_) fail("Cholesky::solve called before factor()");
  return llt_->solve(B);
}

Eigen::MatrixXd Cholesky::solve(const Eigen::SparseMatrix<double>& B) const {
  return solve(Eigen::MatrixXd(B));
}

}  // namespace softcut::solve
