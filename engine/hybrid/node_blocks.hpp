#pragma once
// Blocks of a global stiffness matrix (dof = 3 * node + axis) picked by node
// lists in any order: the hybrid model numbers its unknowns by node set
// (operational first, interface last; surface before interior), which the
// monotone fem::DofMap cannot express.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

namespace softcut::hybrid {

using SparseMatrix = Eigen::SparseMatrix<double>;  // column-major, int indices

// Position of each node in `nodes`, -1 for nodes not listed. (nnode)
std::vector<int> node_positions(const std::vector<int>& nodes, int nnode);

// K restricted to the DOFs of `rows` x `cols`: entry (3a+r, 3b+c) is
// K(3 rows[a] + r, 3 cols[b] + c). (3|rows| x 3|cols|), sorted, compressed.
SparseMatrix node_block(const SparseMatrix& K, const std::vector<int>& rows, const std::vector<int>& cols);

// Scatters a (3|nodes|) vector into a (nnode x 3) field (other rows untouched)
// and gathers it back.
void scatter_nodes(const Eigen::VectorXd& x, const std::vector<int>& nodes, Eigen::MatrixX3d& field);
Eigen::VectorXd gather_nodes(const Eigen::MatrixX3d& field, const std::vector<int>& nodes);

}  // namespace softcut::hybrid
