#pragma once
// Dense Schur complement S = A_II - A_I2 A22^-1 A_2I of a symmetric positive
// definite bordered matrix, taken from ONE sparse Cholesky factorisation of
// [A22 A2I; AI2 AII] ordered with the I block last: the trailing block L_II of
// that factor satisfies L_II L_II^T = S. This avoids the 3|I| right-hand-side
// solves with K22 (K' of a 100k-tet model in seconds instead of minutes).
#include <Eigen/Core>
#include <string>

#include "hybrid/node_blocks.hpp"

namespace softcut::hybrid {

// A22 (n2 x n2, symmetric, both triangles or lower stored), A2I (n2 x nI),
// AII (nI x nI, symmetric); A22 positive definite, the bordered matrix at
// least semidefinite. Returns S (nI x nI), symmetric. Throws softcut::Error
// naming `what` when the factorisation fails (A22 singular).
Eigen::MatrixXd schur_complement(const SparseMatrix& A22, const SparseMatrix& A2I, const Eigen::MatrixXd& AII,
                                 const std::string& what);

}  // namespace softcut::hybrid
