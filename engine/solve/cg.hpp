#pragma once
// Preconditioned conjugate gradient on an abstract symmetric positive definite
// operator, so the same solver serves a plain sparse matrix, the operational
// system (sparse + dense interface block K'), and parity checks for the GPU.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <functional>
#include <vector>

namespace softcut::solve {

// y = A x; x and y have the system size; y is already sized.
using LinearOperator = std::function<void(const Eigen::VectorXd& x, Eigen::VectorXd& y)>;

struct CgOptions {
  double tolerance = 1e-10;   // stop when ||b - A x|| <= tolerance * ||b||
  int max_iterations = 0;     // 0: 10 * system size
};

struct CgResult {
  int iterations = 0;
  double relative_residual = 0;  // ||b - A x|| / ||b|| (recursive residual)
  bool converged = false;
};

// Solves A x = b starting from x (warm start; x is resized and zeroed when its
// size does not match). `precondition` applies M^{-1}.
CgResult pcg(const LinearOperator& apply_A, const LinearOperator& precondition, const Eigen::VectorXd& b,
             Eigen::VectorXd& x, const CgOptions& opt = {});

// Inverted 3x3 diagonal blocks of a symmetric matrix whose DOFs come in node
// triples (block-Jacobi preconditioner). (n/3 blocks)
class BlockJacobi {
 public:
  BlockJacobi() = default;
  explicit BlockJacobi(const Eigen::SparseMatrix<double>& A);
  // Adds a dense symmetric block (e.g. K') on dofs [offset, offset + B.rows()).
  void add_dense(const Eigen::MatrixXd& B, int offset);
  void finalize();  // inverts the blocks
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  LinearOperator as_operator() const;

 private:
  std::vector<Eigen::Matrix3d> blocks_;
};

// y = A x for a fully stored sparse A; A must outlive the operator.
LinearOperator sparse_operator(const Eigen::SparseMatrix<double>& A);

}  // namespace softcut::solve
