#include "hybrid/precompute_estimate.hpp"

#include <Eigen/SparseCore>
#include <algorithm>

#include "hybrid/node_blocks.hpp"
#include "solve/cholesky.hpp"

namespace softcut::hybrid {

PrecomputeEstimate estimate_precompute(const mesh::TetMesh& m, const Partition& p,
                                       const std::vector<int>& nonop_nodes, bool factor) {
  PrecomputeEstimate e;
  const int nn = m.num_nodes();
  const std::vector<int>& tets = p.nonoperational_tets;
  if (tets.empty()) return e;

  // Node -> nonoperational tets (CSR): 16 bytes per tet.
  std::vector<int> start(size_t(nn) + 1, 0);
  for (int t : tets)
    for (int b = 0; b < 4; ++b) ++start[size_t(m.tets(t, b)) + 1];
  for (int v = 0; v < nn; ++v) start[size_t(v) + 1] += start[size_t(v)];
  std::vector<int> incident(size_t(start.back()));
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int t : tets)
      for (int b = 0; b < 4; ++b) incident[size_t(fill[size_t(m.tets(t, b))]++)] = t;
  }

  // Each node's distinct neighbours through those tets (itself included):
  // the 3x3 blocks of its column of K^non, and by node set of K22 and K2I.
  const std::vector<int> pos2 = node_positions(nonop_nodes, nn);
  std::vector<int> mark(size_t(nn), -1);
  std::vector<Eigen::Triplet<double>> graph;  // K22's node graph, lower triangle
  double all = 0, k22 = 0, k2I = 0;
  for (int v = 0; v < nn; ++v) {
    if (start[size_t(v)] == start[size_t(v) + 1]) continue;
    const bool v2 = pos2[size_t(v)] >= 0;
    for (int k = start[size_t(v)]; k < start[size_t(v) + 1]; ++k)
      for (int a = 0; a < 4; ++a) {
        const int u = m.tets(incident[size_t(k)], a);
        if (mark[size_t(u)] == v) continue;
        mark[size_t(u)] = v;
        ++all;
        const bool u2 = pos2[size_t(u)] >= 0;
        if (v2 && u2) {
          ++k22;
          if (factor && pos2[size_t(u)] >= pos2[size_t(v)])
            graph.emplace_back(pos2[size_t(u)], pos2[size_t(v)], u == v ? 1.0 : -0.1);
        }
        if (v2 && p.node_set[size_t(u)] == NodeSet::interface) ++k2I;
      }
  }
  e.knon_nonzeros = 9 * all;
  e.k22_nonzeros = 9 * k22;
  e.k2I_nonzeros = 9 * k2I;
  // Compressed sparse columns: 8 bytes of value and 4 of row index per entry;
  // assemble_stiffness's neighbour lists take 16 ints per tet meanwhile.
  e.assembly_bytes = 12 * (e.knon_nonzeros + e.k22_nonzeros + 2 * e.k2I_nonzeros) + 64.0 * double(tets.size()) +
                     4.0 * 3 * double(nn);
  if (factor && !nonop_nodes.empty()) {
    const int n2 = int(nonop_nodes.size());
    Eigen::SparseMatrix<double> G(n2, n2);
    G.setFromTriplets(graph.begin(), graph.end());
    graph = {};
    // A node's lower-triangle factor entries are 3x3 blocks off the
    // diagonal and a lower-triangular 3x3 block (6 entries) on it.
    const double node_lnz = solve::Cholesky::symbolic_nonzeros(G);
    e.factor_nonzeros = 9 * (node_lnz - n2) + 6.0 * n2;
    e.factor_bytes = 16 * e.factor_nonzeros;
  }
  return e;
}

}  // namespace softcut::hybrid
