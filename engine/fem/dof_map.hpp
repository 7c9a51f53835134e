#pragma once
// Fixed-node elimination. The unknowns of a system are the DOFs of nodes that
// are referenced by some tet and not fixed; DofMap numbers them compactly.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "fem/assembly.hpp"

namespace softcut::fem {

struct DofMap {
  std::vector<int> reduced;  // (3 nnode) reduced index of each global dof, -1 if eliminated
  std::vector<int> global;   // (nfree) global dof of each reduced index, increasing
  int size() const { return int(global.size()); }
};

// node_free (nnode): nonzero for nodes whose three DOFs are unknowns.
DofMap make_dof_map(const std::vector<char>& node_free);

// Rows and columns of `map` taken from K (3 nnode square) -> (nfree x nfree).
SparseMatrix restrict_matrix(const SparseMatrix& K, const DofMap& map);
// Rows of `map` / columns of `cols` from K -> (rows.size() x cols.size()).
SparseMatrix restrict_matrix(const SparseMatrix& K, const DofMap& rows, const DofMap& cols);

Eigen::VectorXd restrict_vector(const Eigen::VectorXd& full, const DofMap& map);  // (nfree)
// Scatters a reduced vector into a full (3 nnode) vector, zeros elsewhere.
Eigen::VectorXd expand_vector(const Eigen::VectorXd& reduced, const DofMap& map, int nnode);

// (nnode x 3) displacement field <-> (3 nnode) dof vector.
Eigen::VectorXd flatten(const Eigen::MatrixX3d& field);
Eigen::MatrixX3d unflatten(const Eigen::VectorXd& dofs);

}  // namespace softcut::fem
