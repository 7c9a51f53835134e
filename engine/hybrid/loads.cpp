#include "hybrid/loads.hpp"

#include "core/error.hpp"

namespace softcut::hybrid {

NodeSet check_load(const Partition& p, int node, const Eigen::Vector3d& force, const std::string& what) {
  if (node < 0 || node >= p.num_nodes())
    fail(what, " on node ", node, ": no such node (the mesh has ", p.num_nodes(), " nodes, ids 0..",
         p.num_nodes() - 1, ")");
  if (!force.allFinite())
    fail(what, " on node ", node, ": the force (", force.x(), ", ", force.y(), ", ", force.z(),
         ") N has NaN or Inf components");
  const NodeSet s = p.node_set[size_t(node)];
  switch (s) {
    case NodeSet::unused:
      fail(what, " on node ", node, ": the node is used by no tet, so it has no stiffness; load a node of the mesh");
    case NodeSet::fixed:
      fail(what, " on node ", node, ": the node is fixed (prescribed zero displacement), so a force there has no "
           "effect; load a free node or unfix it");
    case NodeSet::interior:
      fail(what, " on node ", node, ": the node is an interior node of the nonoperational region, whose degrees "
           "of freedom were condensed away in the precompute (paper Eq. 16); load a surface node instead, or make "
           "the region around node ", node, " operational");
    default: return s;
  }
}

}  // namespace softcut::hybrid
