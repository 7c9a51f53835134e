#include "gpu/block_system.hpp"

#include <Eigen/LU>
#include <algorithm>

#include "core/error.hpp"

namespace softcut::gpu {

std::size_t BlockSystem::bytes(std::size_t s) const {
  return 4 * (row_ptr.size() + col.size()) + s * (values.size() + dense.size() + diag_inverse.size());
}

void BlockSystem::apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  y.setZero(size());
  for (int I = 0; I < num_blocks; ++I)
    for (std::uint32_t k = row_ptr[size_t(I)]; k < row_ptr[size_t(I) + 1]; ++k) {
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> B(values.data() + 9 * k);
      y.segment<3>(3 * I) += B * x.segment<3>(3 * Eigen::Index(col[k]));
    }
  if (dense_size > 0) {
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> D(
        dense.data(), dense_size, dense_size);
    y.segment(dense_offset, dense_size) += D * x.segment(dense_offset, dense_size);
  }
}

BlockSystem make_block_system(const Eigen::SparseMatrix<double>& K, const Eigen::MatrixXd* dense) {
  if (K.rows() != K.cols() || K.rows() % 3 != 0)
    fail("GPU solver: the system matrix must be square with DOFs in node triples, got ", K.rows(), "x", K.cols());
  BlockSystem s;
  s.num_blocks = int(K.rows() / 3);
  const int nb = s.num_blocks;
  // K is symmetric, so block row I = transpose of block column I: walk the
  // columns of node I and record block (J, I)^T as block (I, J).
  std::vector<std::vector<std::pair<int, int>>> entries(size_t(nb));  // per block row: (J, position in col)
  s.row_ptr.assign(size_t(nb) + 1, 0);
  for (int I = 0; I < nb; ++I) {
    std::vector<int> js;
    for (int c = 0; c < 3; ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(K, 3 * I + c); it; ++it) js.push_back(int(it.row() / 3));
    std::sort(js.begin(), js.end());
    js.erase(std::unique(js.begin(), js.end()), js.end());
    s.row_ptr[size_t(I) + 1] = s.row_ptr[size_t(I)] + std::uint32_t(js.size());
    for (int J : js) s.col.push_back(std::uint32_t(J));
  }
  s.values.assign(9 * s.col.size(), 0.0);
  for (int I = 0; I < nb; ++I) {
    const auto first = s.col.begin() + s.row_ptr[size_t(I)], last = s.col.begin() + s.row_ptr[size_t(I) + 1];
    for (int c = 0; c < 3; ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(K, 3 * I + c); it; ++it) {
        // Entry K(row, 3I + c) = K(3I + c, row) by symmetry: block row I, column row/3.
        const int J = int(it.row() / 3);
        const auto k = size_t(std::lower_bound(first, last, std::uint32_t(J)) - s.col.begin());
        s.values[9 * k + size_t(3 * c + it.row() % 3)] = it.value();
      }
  }
  if (dense && dense->rows() > 0) {
    if (dense->rows() != dense->cols() || dense->rows() % 3 != 0 || dense->rows() > K.rows())
      fail("GPU solver: the dense block must be square, in node triples and fit the system");
    s.dense_size = int(dense->rows());
    s.dense_offset = int(K.rows() - dense->rows());
    s.dense.resize(size_t(s.dense_size) * size_t(s.dense_size));
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(s.dense.data(), s.dense_size,
                                                                                       s.dense_size) = *dense;
  }
  s.diag_inverse.assign(9 * size_t(nb), 0.0);
  for (int I = 0; I < nb; ++I) {
    Eigen::Matrix3d B = Eigen::Matrix3d::Zero();
    for (std::uint32_t k = s.row_ptr[size_t(I)]; k < s.row_ptr[size_t(I) + 1]; ++k)
      if (int(s.col[k]) == I) B = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(s.values.data() + 9 * k);
    if (3 * I >= s.dense_offset && s.dense_size > 0) {
      const int d = 3 * I - s.dense_offset;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) B(r, c) += s.dense[size_t(d + r) * size_t(s.dense_size) + size_t(d + c)];
    }
    if (!(B.determinant() > 0))
      fail("GPU solver: node block ", I, " of the operational system has no stiffness (is the node fixed or "
           "unconnected?)");
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(s.diag_inverse.data() + 9 * size_t(I)) = B.inverse();
  }
  return s;
}

}  // namespace softcut::gpu
