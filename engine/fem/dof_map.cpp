#include "fem/dof_map.hpp"

#include "core/error.hpp"

namespace softcut::fem {

DofMap make_dof_map(const std::vector<char>& node_free) {
  DofMap map;
  map.reduced.assign(3 * node_free.size(), -1);
  for (size_t n = 0; n < node_free.size(); ++n)
    if (node_free[n])
      for (int c = 0; c < 3; ++c) {
        map.reduced[3 * n + size_t(c)] = int(map.global.size());
        map.global.push_back(int(3 * n) + c);
      }
  return map;
}

SparseMatrix restrict_matrix(const SparseMatrix& K, const DofMap& rows, const DofMap& cols) {
  if (size_t(K.rows()) != rows.reduced.size() || size_t(K.cols()) != cols.reduced.size())
    fail("restrict_matrix: a ", K.rows(), "x", K.cols(), " matrix with DOF maps over ", rows.reduced.size(), " and ",
         cols.reduced.size(), " DOFs");
  SparseMatrix R(rows.size(), cols.size());
  // Columns come out in order and rows within a column stay sorted, because
  // both maps are monotone: fill the CSC arrays directly.
  std::vector<int> outer(size_t(cols.size()) + 1, 0);
  std::vector<int> inner;
  std::vector<double> value;
  for (int jc = 0; jc < cols.size(); ++jc) {
    for (SparseMatrix::InnerIterator it(K, cols.global[size_t(jc)]); it; ++it) {
      const int r = rows.reduced[size_t(it.row())];
      if (r >= 0) {
        inner.push_back(r);
        value.push_back(it.value());
      }
    }
    outer[size_t(jc) + 1] = int(inner.size());
  }
  R.resizeNonZeros(Eigen::Index(inner.size()));
  std::copy(outer.begin(), outer.end(), R.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), R.innerIndexPtr());
  std::copy(value.begin(), value.end(), R.valuePtr());
  return R;
}

SparseMatrix restrict_matrix(const SparseMatrix& K, const DofMap& map) {
  return restrict_matrix(K, map, map);
}

Eigen::VectorXd restrict_vector(const Eigen::VectorXd& full, const DofMap& map) {
  if (size_t(full.size()) != map.reduced.size())
    fail("restrict_vector: a vector of size ", full.size(), " with a DOF map over ", map.reduced.size(), " DOFs");
  Eigen::VectorXd r(map.size());
  for (int i = 0; i < map.size(); ++i) r(i) = full(map.global[size_t(i)]);
  return r;
}

Eigen::VectorXd expand_vector(const Eigen::VectorXd& reduced, const DofMap& map, int nnode) {
  if (reduced.size() != map.size() || map.reduced.size() != 3 * size_t(nnode))
    fail("expand_vector: a reduced vector of size ", reduced.size(), " for a DOF map of ", map.size(), " unknowns over ",
         map.reduced.size(), " DOFs (", nnode, " nodes)");
  Eigen::VectorXd full = Eigen::VectorXd::Zero(3 * Eigen::Index(nnode));
  for (int i = 0; i < map.size(); ++i) full(map.global[size_t(i)]) = reduced(i);
  return full;
}

Eigen::VectorXd flatten(const Eigen::MatrixX3d& field) {
  Eigen::VectorXd v(field.rows() * 3);
  for (Eigen::Index i = 0; i < field.rows(); ++i) v.segment<3>(3 * i) = field.row(i).transpose();
  return v;
}

Eigen::MatrixX3d unflatten(const Eigen::VectorXd& dofs) {
  if (dofs.size() % 3 != 0) fail("unflatten: ", dofs.size(), " DOFs is not a multiple of 3");
  Eigen::MatrixX3d f(dofs.size() / 3, 3);
  for (Eigen::Index i = 0; i < f.rows(); ++i) f.row(i) = dofs.segment<3>(3 * i).transpose();
  return f;
}

}  // namespace softcut::fem
