#pragma once
// What precompute() will allocate, known before it assembles K^non: the
// sparse matrices from the nonoperational tets' node pairs (counted, nothing
// of matrix size allocated) and the K22 factor from CHOLMOD's symbolic
// analysis of the node graph (9x smaller than K22's, the same ordering
// methods). precompute() refuses a model over its byte limit from this
// before anything large exists: a 2M-tet box was assembled (2.2 GB, 34 s)
// before the 512 MiB sandbox budget refused its factor.
#include <vector>

#include "hybrid/partition.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::hybrid {

struct PrecomputeEstimate {
  double knon_nonzeros = 0;    // of K^non (3 nnode)^2, scalar entries
  double k22_nonzeros = 0;     // of K22 (3|2|)^2
  double k2I_nonzeros = 0;     // of K2I (3|2| x 3|I|)
  double assembly_bytes = 0;   // K^non, its pattern's scratch, K22, K2I and KI2 alive at once
  double factor_nonzeros = 0;  // of the K22 factor, estimated (0 when not asked for)
  double factor_bytes = 0;     // as solve::Cholesky::factor counts them (16 bytes each)
};

// `nonop_nodes`: the K22 node order (surface then interior ids). The factor
// estimate is made only when `factor` is true (it costs a symbolic analysis
// of a graph of |2| nodes).
PrecomputeEstimate estimate_precompute(const mesh::TetMesh& m, const Partition& p,
                                       const std::vector<int>& nonop_nodes, bool factor);

}  // namespace softcut::hybrid
