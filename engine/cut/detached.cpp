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
  const fem::Parts parts = fem::connected_parts(m);
  const size_t np = size_t(parts.count);
  std::vector<Eigen::Vector3d> lo(np, Eigen::Vector3d::Constant(1e300)), hi(np, Eigen::Vector3d::Constant(-1e300));
  std::vector<int> first(np, -1), far(np, -1), count(np, 0);
  for (int v = 0; v < nn; ++v) {
    const int p = parts.node_part[size_t(v)];
    if (p < 0) continue;
    lo[size_t(p)] = lo[size_t(p)].cwiseMin(m.node(v));
    hi[size_t(p)] = hi[size_t(p)].cwiseMax(m.node(v));
    if (!node_fixed[size_t(v)]) continue;
    ++count[size_t(p)];
    if (first[size_t(p)] < 0) first[size_t(p)] = v;
  }
  // Anchored: a fixed node away from the first one (beyond a point), and one
  // away from the line through the first and the farthest (beyond a line).
  std::vector<double> far_dist(np, 0.0), line_dist(np, 0.0);
  for (int v = 0; v < nn; ++v) {
    const int p = parts.node_part[size_t(v)];
    if (p < 0 || !node_fixed[size_t(v)]) continue;
    const double d = (m.node(v) - m.node(first[size_t(p)])).norm();
    if (d > far_dist[size_t(p)]) {
      far_dist[size_t(p)] = d;
      far[size_t(p)] = v;
    }
  }
  for (int v = 0; v < nn; ++v) {
    const int p = parts.node_part[size_t(v)];
    if (p < 0 || !node_fixed[size_t(v)] || far[size_t(p)] < 0) continue;
    const Eigen::Vector3d a = m.node(first[size_t(p)]);
    const Eigen::Vector3d dir = (m.node(far[size_t(p)]) - a).normalized();
    const Eigen::Vector3d r = m.node(v) - a;
    line_dist[size_t(p)] = std::max(line_dist[size_t(p)], (r - r.dot(dir) * dir).norm());
  }
  std::vector<int> piece_of(np, -1);
  std::vector<DetachedPiece> pieces;
  for (size_t p = 0; p < np; ++p) {
    const double size = (hi[p] - lo[p]).norm();
    const bool anchored = count[p] > 0 && far_dist[p] > 1e-9 * size && line_dist[p] > 1e-9 * size;
    if (anchored) continue;
    piece_of[p] = int(pieces.size());
    pieces.emplace_back().fixed_nodes = count[p];
  }
  if (pieces.empty()) return pieces;
  for (int v = 0; v < nn; ++v) {
    const int p = parts.node_part[size_t(v)];
    if (p >= 0 && piece_of[size_t(p)] >= 0) pieces[size_t(piece_of[size_t(p)])].nodes.push_back(v);
  }
  for (int t = 0; t < nt; ++t) {
    const int q = piece_of[size_t(parts.node_part[size_t(m.tets(t, 0))])];
    if (q >= 0) pieces[size_t(q)].tets.push_back(t);
  }
  return pieces;
}

}  // namespace softcut::cut
