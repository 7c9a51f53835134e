#include "solve/cg.hpp"

#include <Eigen/LU>
#include <cmath>

#include "core/error.hpp"

namespace softcut::solve {

CgResult pcg(const LinearOperator& apply_A, const LinearOperator& precondition, const Eigen::VectorXd& b,
             Eigen::VectorXd& x, const CgOptions& opt) {
  const Eigen::Index n = b.size();
  if (x.size() != n) x = Eigen::VectorXd::Zero(n);
  CgResult res;
  if (!b.allFinite()) fail("conjugate gradient: the right-hand side has NaN or Inf entries");
  if (!x.allFinite()) fail("conjugate gradient: the warm start has NaN or Inf entries; start from zero");
  const double bnorm = b.norm();
  if (bnorm == 0) {
    x.setZero();
    res.converged = true;
    return res;
  }
  const int max_it = opt.max_iterations > 0 ? opt.max_iterations : int(10 * std::max<Eigen::Index>(n, 10));
  Eigen::VectorXd r(n), z(n), p(n), Ap(n);
  apply_A(x, Ap);
  r = b - Ap;
  double rnorm = r.norm();
  if (rnorm <= opt.tolerance * bnorm) {
    res.relative_residual = rnorm / bnorm;
    res.converged = true;
    return res;
  }
  precondition(r, z);
  p = z;
  double rz = r.dot(z);
  for (int it = 1; it <= max_it; ++it) {
    apply_A(p, Ap);
    const double pAp = p.dot(Ap);
    if (!(pAp > 0)) fail("conjugate gradient: the operator is not positive definite (p^T A p = ", pAp, ")");
    const double alpha = rz / pAp;
    x.noalias() += alpha * p;
    r.noalias() -= alpha * Ap;
    rnorm = r.norm();
    res.iterations = it;
    if (rnorm <= opt.tolerance * bnorm) {
      res.converged = true;
      break;
    }
    precondition(r, z);
    const double rz_new = r.dot(z);
    p = z + (rz_new / rz) * p;
    rz = rz_new;
  }
  res.relative_residual = rnorm / bnorm;
  return res;
}

BlockJacobi::BlockJacobi(const Eigen::SparseMatrix<double>& A) {
  if (A.rows() != A.cols() || A.rows() % 3 != 0)
    fail("block-Jacobi preconditioner: needs a square matrix with 3 DOFs per node, got ", A.rows(), "x", A.cols());
  blocks_.assign(size_t(A.rows() / 3), Eigen::Matrix3d::Zero());
  for (int col = 0; col < A.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, col); it; ++it)
      if (it.row() / 3 == col / 3) blocks_[size_t(col / 3)](it.row() % 3, col % 3) = it.value();
}

void BlockJacobi::add_dense(const Eigen::MatrixXd& B, int offset) {
  if (B.rows() != B.cols() || B.rows() % 3 != 0 || offset % 3 != 0 || offset < 0 ||
      size_t(offset + B.rows()) > 3 * blocks_.size())
    fail("block-Jacobi preconditioner: dense block ", B.rows(), "x", B.cols(), " at offset ", offset,
         " does not fit node triples of a ", 3 * blocks_.size(), "-DOF system");
  for (Eigen::Index k = 0; k < B.rows() / 3; ++k)
    blocks_[size_t(offset / 3 + k)] += B.block<3, 3>(3 * k, 3 * k);
}

void BlockJacobi::finalize() {
  for (auto& b : blocks_) {
    // A node with no stiffness (should not happen for referenced nodes): identity.
    b = b.determinant() > 0 ? Eigen::Matrix3d(b.inverse()) : Eigen::Matrix3d::Identity();
  }
}

void BlockJacobi::apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  if (x.size() != Eigen::Index(3 * blocks_.size()) || y.size() != x.size())
    fail("block-Jacobi preconditioner: vectors of size ", x.size(), " and ", y.size(), " for ", 3 * blocks_.size(),
         " DOFs");
  for (size_t k = 0; k < blocks_.size(); ++k) y.segment<3>(3 * Eigen::Index(k)) = blocks_[k] * x.segment<3>(3 * Eigen::Index(k));
}

LinearOperator BlockJacobi::as_operator() const {
  return [this](const Eigen::VectorXd& x, Eigen::VectorXd& y) { apply(x, y); };
}

LinearOperator sparse_operator(const Eigen::SparseMatrix<double>& A) {
  return [&A](const Eigen::VectorXd& x, Eigen::VectorXd& y) { y.noalias() = A * x; };
}

}  // namespace softcut::solve
