#pragma once
// The operational system in the layout the compute shaders read: 3x3
// block-sparse rows (BSR) for the sparse part plus a dense block on the
// trailing DOFs (the interface block K'). Built on the CPU, testable without GL.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

namespace softcut::gpu {

struct BlockSystem {
  int num_blocks = 0;                 // node count nb; system size n = 3 nb
  std::vector<std::uint32_t> row_ptr; // (nb + 1) first block of each block row
  std::vector<std::uint32_t> col;     // (nnzb) block column of each block
  std::vector<double> values;         // (9 nnzb) row-major 3x3 blocks, N/m
  int dense_offset = 0;               // first DOF of the dense block (a multiple of 3)
  int dense_size = 0;                 // m = 3 |I|
  std::vector<double> dense;          // (m x m) row-major, N/m, added on [offset, offset + m)
  std::vector<double> diag_inverse;   // (9 nb) row-major inverses of the 3x3 diagonal blocks of A

  int size() const { return 3 * num_blocks; }
  std::size_t bytes(std::size_t scalar_bytes) const;  // device memory for the matrix data
  // y = A x on the CPU in double (reference for tests).
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
};

// K (n x n, both triangles stored, DOFs in node triples) plus an optional
// dense symmetric block D on the last D.rows() DOFs. Missing entries of a
// stored 3x3 block are zero. Throws softcut::Error on a non-square K, n not a
// multiple of 3, or a zero/singular diagonal block.
BlockSystem make_block_system(const Eigen::SparseMatrix<double>& K, const Eigen::MatrixXd* dense = nullptr);

}  // namespace softcut::gpu
