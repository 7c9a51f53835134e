#include "hybrid/node_blocks.hpp"

#include <algorithm>
#include <utility>

namespace softcut::hybrid {

std::vector<int> node_positions(const std::vector<int>& nodes, int nnode) {
  std::vector<int> pos(size_t(nnode), -1);
  for (size_t k = 0; k < nodes.size(); ++k) pos[size_t(nodes[k])] = int(k);
  return pos;
}

SparseMatrix node_block(const SparseMatrix& K, const std::vector<int>& rows, const std::vector<int>& cols) {
  const int nnode = int(K.rows() / 3);
  const std::vector<int> row_pos = node_positions(rows, nnode);
  SparseMatrix B(Eigen::Index(3 * rows.size()), Eigen::Index(3 * cols.size()));
  std::vector<int> outer(3 * cols.size() + 1, 0);
  std::vector<std::pair<int, double>> entries, column;
  for (size_t b = 0; b < cols.size(); ++b)
    for (int c = 0; c < 3; ++c) {
      column.clear();
      for (SparseMatrix::InnerIterator it(K, 3 * cols[b] + c); it; ++it) {
        const int a = row_pos[size_t(it.row() / 3)];
        if (a >= 0) column.emplace_back(3 * a + int(it.row() % 3), it.value());
      }
      std::sort(column.begin(), column.end(),
                [](const auto& x, const auto& y) { return x.first < y.first; });
      entries.insert(entries.end(), column.begin(), column.end());
      outer[3 * b + size_t(c) + 1] = int(entries.size());
    }
  B.resizeNonZeros(Eigen::Index(entries.size()));
  std::copy(outer.begin(), outer.end(), B.outerIndexPtr());
  for (size_t k = 0; k < entries.size(); ++k) {
    B.innerIndexPtr()[k] = entries[k].first;
    B.valuePtr()[k] = entries[k].second;
  }
  return B;
}

void scatter_nodes(const Eigen::VectorXd& x, const std::vector<int>& nodes, Eigen::MatrixX3d& field) {
  for (size_t k = 0; k < nodes.size(); ++k) field.row(nodes[k]) = x.segment<3>(3 * Eigen::Index(k)).transpose();
}

Eigen::VectorXd gather_nodes(const Eigen::MatrixX3d& field, const std::vector<int>& nodes) {
  Eigen::VectorXd x(3 * Eigen::Index(nodes.size()));
  for (size_t k = 0; k < nodes.size(); ++k) x.segment<3>(3 * Eigen::Index(k)) = field.row(nodes[k]).transpose();
  return x;
}

}  // namespace softcut::hybrid
