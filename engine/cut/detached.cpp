#include "cut/detached.hpp"

#include <Eigen/Core>
#include <algorithm>

#include "core/error.hpp"
#include "fem/anchoring.hpp"

namespace softcut::cut {

std::vector<DetachedPiece> find_detached(const mesh::TetMesh& m, const std::vector<char>& node_fixed) {
  const int nn = m.num_nodes(), nt = m.num_tets();
  if (int(node_fixed.size()) != nn)
    fail("find_detached: fixed-node flags for ", node_fixed.size(), " nodes, but the mesh has ", nn);
  const fem::Anchoring A = fem::anchor_parts(m, {}, node_fixed);
  const size_t np = A.parts.size();
  // A node of an anchored part stays with the body (a hinge node included).
  std::vector<char> in_anchored(size_t(nn), 0);
  for (int t = 0; t < nt; ++t)
    if (A.parts[size_t(A.tet_part[size_t(t)])].anchored)
      for (int k = 0; k < 4; ++k) in_anchored[size_t(m.tets(t, k))] = 1;
  // Unanchored parts in order of their smallest node id.
  std::vector<int> order;
  for (size_t p = 0; p < np; ++p)
    if (!A.parts[p].anchored) order.push_back(int(p));
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return A.parts[size_t(a)].first_node < A.parts[size_t(b)].first_node; });
  std::vector<int> piece_of(np, -1);
  std::vector<DetachedPiece> pieces(order.size());
  for (size_t k = 0; k < order.size(); ++k) piece_of[size_t(order[k])] = int(k);
  std::vector<int> seen(size_t(nn), -1);
  for (int t = 0; t < nt; ++t) {
    const int q = piece_of[size_t(A.tet_part[size_t(t)])];
    if (q < 0) continue;
    pieces[size_t(q)].tets.push_back(t);
    for (int k = 0; k < 4; ++k) {
      const int v = m.tets(t, k);
      if (in_anchored[size_t(v)] || seen[size_t(v)] == q) continue;
      seen[size_t(v)] = q;
      pieces[size_t(q)].nodes.push_back(v);
    }
  }
  for (DetachedPiece& d : pieces) {
    std::sort(d.nodes.begin(), d.nodes.end());  // each node was added once (`seen`)
    for (int v : d.nodes) d.fixed_nodes += node_fixed[size_t(v)] != 0;
  }
  return pieces;
}

}  // namespace softcut::cut
