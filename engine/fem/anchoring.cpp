#include "fem/anchoring.hpp"

#include <numeric>

#include "core/error.hpp"

namespace softcut::fem {

namespace {

int find_root(std::vector<int>& parent, int i) {
  while (parent[size_t(i)] != i) {
    parent[size_t(i)] = parent[size_t(parent[size_t(i)])];  // path halving
    i = parent[size_t(i)];
  }
  return i;
}

}  // namespace

Parts connected_parts(const mesh::TetMesh& m, const std::vector<int>& tets_in) {
  const int nn = m.num_nodes(), nt = m.num_tets();
  std::vector<int> parent(static_cast<size_t>(nn));
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> used(size_t(nn), 0);
  auto visit = [&](int t) {
    if (t < 0 || t >= nt) fail("connected_parts: tet id ", t, " is out of range 0..", nt - 1);
    for (int k = 0; k < 4; ++k) {
      const int v = m.tets(t, k);
      if (v < 0 || v >= nn) fail("connected_parts: tetrahedron ", t, " refers to node ", v, " of ", nn);
      used[size_t(v)] = 1;
      if (k == 0) continue;
      const int a = find_root(parent, m.tets(t, 0)), b = find_root(parent, v);
      if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);  // root = smallest id
    }
  };
  if (tets_in.empty())
    for (int t = 0; t < nt; ++t) visit(t);
  else
    for (int t : tets_in) visit(t);

  Parts parts;
  parts.node_part.assign(size_t(nn), -1);
  std::vector<int> root_part(size_t(nn), -1);
  for (int i = 0; i < nn; ++i) {
    if (!used[size_t(i)]) continue;
    const int r = find_root(parent, i);
    if (root_part[size_t(r)] < 0) root_part[size_t(r)] = parts.count++;
    parts.node_part[size_t(i)] = root_part[size_t(r)];
  }
  parts.tet_count.assign(size_t(parts.count), 0);
  auto count_tet = [&](int t) { ++parts.tet_count[size_t(parts.node_part[size_t(m.tets(t, 0))])]; };
  if (tets_in.empty())
    for (int t = 0; t < nt; ++t) count_tet(t);
  else
    for (int t : tets_in) count_tet(t);
  return parts;
}

void check_anchored(const mesh::TetMesh& m, const std::vector<int>& tets, const std::vector<char>& node_fixed,
                    const std::string& what) {
  const int nn = m.num_nodes();
  if (int(node_fixed.size()) != nn)
    fail(what, ": fixed-node flags for ", node_fixed.size(), " nodes, but the mesh has ", nn);
  const Parts parts = connected_parts(m, tets);
  const size_t np = size_t(parts.count);
  std::vector<int> first_node(np, -1), first_fixed(np, -1), far_fixed(np, -1), off_line(np, -1);
  std::vector<Eigen::Vector3d> lo(np, Eigen::Vector3d::Constant(1e300)), hi(np, Eigen::Vector3d::Constant(-1e300));
  for (int i = 0; i < nn; ++i) {
    const int p = parts.node_part[size_t(i)];
    if (p < 0) continue;
    if (first_node[size_t(p)] < 0) first_node[size_t(p)] = i;
    lo[size_t(p)] = lo[size_t(p)].cwiseMin(m.node(i));
    hi[size_t(p)] = hi[size_t(p)].cwiseMax(m.node(i));
  }
  // Fixed nodes per part: the first one, the farthest from it, and the
  // farthest from the line through those two.
  std::vector<double> far_dist(np, 0.0), line_dist(np, 0.0);
  for (int i = 0; i < nn; ++i) {
    const int p = parts.node_part[size_t(i)];
    if (p < 0 || !node_fixed[size_t(i)]) continue;
    if (first_fixed[size_t(p)] < 0) first_fixed[size_t(p)] = i;
    const double d = (m.node(i) - m.node(first_fixed[size_t(p)])).norm();
    if (d > far_dist[size_t(p)]) {
      far_dist[size_t(p)] = d;
      far_fixed[size_t(p)] = i;
    }
  }
  for (int i = 0; i < nn; ++i) {
    const int p = parts.node_part[size_t(i)];
    if (p < 0 || !node_fixed[size_t(i)] || far_fixed[size_t(p)] < 0) continue;
    const Eigen::Vector3d a = m.node(first_fixed[size_t(p)]);
    const Eigen::Vector3d dir = (m.node(far_fixed[size_t(p)]) - a).normalized();
    const Eigen::Vector3d r = m.node(i) - a;
    const double d = (r - r.dot(dir) * dir).norm();
    if (d > line_dist[size_t(p)]) {
      line_dist[size_t(p)] = d;
      off_line[size_t(p)] = i;
    }
  }
  for (size_t p = 0; p < np; ++p) {
    const double size = (hi[p] - lo[p]).norm();
    const std::string part =
        cat("the part of the body containing node ", first_node[p], " (", parts.tet_count[p],
            " tets, bounding box [", lo[p].x(), ", ", lo[p].y(), ", ", lo[p].z(), "] .. [", hi[p].x(), ", ",
            hi[p].y(), ", ", hi[p].z(), "] m", parts.count > 1 ? cat(", one of ", parts.count, " parts") : "", ")");
    if (first_fixed[p] < 0)
      fail(what, ": ", part, " has no fixed node, so it can move freely and the stiffness matrix is singular; "
           "fix at least three of its nodes that are not on one line, or remove those tets");
    if (far_dist[p] <= 1e-9 * size)
      fail(what, ": ", part, " is fixed only at node ", first_fixed[p],
           ", so it can rotate about that point and the stiffness matrix is singular; "
           "fix at least three of its nodes that are not on one line");
    if (line_dist[p] <= 1e-9 * size)
      fail(what, ": ", part, " is fixed only along the line through nodes ", first_fixed[p], " and ",
           far_fixed[p], ", so it can rotate about that line and the stiffness matrix is singular; "
           "fix a node off that line too");
  }
}

}  // namespace softcut::fem
