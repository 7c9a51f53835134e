#pragma once
// Point loads of one frame and the checks that keep them meaningful for the
// hybrid model: only nodes whose DOFs survive condensation may be loaded.
#include <Eigen/Core>
#include <string>

#include "hybrid/partition.hpp"

namespace softcut::hybrid {

struct Load {
  int node = -1;                                     // mesh node id
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // N
};

// Throws softcut::Error (prefixed with `what`) when `force` is not finite or
// `node` is unknown, used by no tet, fixed, or an interior nonoperational node
// (condensed away: the message suggests loading a surface node or making the
// region operational). Returns the node's set (operational, interface or surface).
NodeSet check_load(const Partition& p, int node, const Eigen::Vector3d& force, const std::string& what = "load");

}  // namespace softcut::hybrid
