#include "fem/anchoring.hpp"

#include <algorithm>
#include <array>
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
  if (int(node_fixed.size()) != m.num_nodes())
    fail(what, ": fixed-node flags for ", node_fixed.size(), " nodes, but the mesh has ", m.num_nodes());
  const Anchoring A = anchor_parts(m, tets, node_fixed);
  for (size_t p = 0; p < A.parts.size(); ++p)
    if (!A.parts[p].anchored) fail(what, ": ", A.describe(int(p)), " ", A.why_loose(int(p)));
}

}  // namespace softcut::fem

namespace softcut::fem {

namespace {

// Three pinned points not on one line (within tol): the test of anchored.
Anchoring::Pin pin_kind(const mesh::TetMesh& m, const std::vector<int>& pinned, double tol, int& a, int& b) {
  a = b = -1;
  if (pinned.empty()) return Anchoring::Pin::none;
  a = pinned.front();
  double far = 0;
  for (int v : pinned)
    if (double d = (m.node(v) - m.node(a)).norm(); d > far) far = d, b = v;
  if (far <= tol) {
    b = -1;
    return Anchoring::Pin::point;
  }
  const Eigen::Vector3d dir = (m.node(b) - m.node(a)).normalized();
  for (int v : pinned) {
    const Eigen::Vector3d r = m.node(v) - m.node(a);
    if ((r - r.dot(dir) * dir).norm() > tol) return Anchoring::Pin::none;  // anchored (caller checks)
  }
  return Anchoring::Pin::line;
}

}  // namespace

Anchoring anchor_parts(const mesh::TetMesh& m, const std::vector<int>& tets_in, const std::vector<char>& node_fixed) {
  const int nn = m.num_nodes(), nt = m.num_tets();
  if (int(node_fixed.size()) != nn)
    fail("anchor_parts: fixed-node flags for ", node_fixed.size(), " nodes, but the mesh has ", nn);
  std::vector<int> tets = tets_in;
  if (tets.empty()) {
    tets.resize(size_t(nt));
    std::iota(tets.begin(), tets.end(), 0);
  }
  for (int t : tets)
    if (t < 0 || t >= nt) fail("anchor_parts: tet id ", t, " is out of range 0..", nt - 1);
  // Faces as sorted node triples; tets sharing one are one rigid part.
  struct Face {
    std::array<int, 3> key;
    int tet;
  };
  std::vector<Face> faces;
  faces.reserve(4 * tets.size());
  for (int t : tets)
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> k;
      for (int j = 0, c = 0; j < 4; ++j)
        if (j != f) k[size_t(c++)] = m.tets(t, j);
      std::sort(k.begin(), k.end());
      faces.push_back({k, t});
    }
  std::sort(faces.begin(), faces.end(), [](const Face& x, const Face& y) { return x.key < y.key; });
  std::vector<int> parent(static_cast<size_t>(nt));
  std::iota(parent.begin(), parent.end(), 0);
  for (size_t i = 1; i < faces.size(); ++i)
    if (faces[i].key == faces[i - 1].key) {
      const int a = find_root(parent, faces[i].tet), b = find_root(parent, faces[i - 1].tet);
      if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
    }
  Anchoring A;
  A.tet_part.assign(size_t(nt), -1);
  std::vector<int> root_part(size_t(nt), -1);
  std::vector<int> sorted = tets;
  std::sort(sorted.begin(), sorted.end());
  for (int t : sorted) {
    const int r = find_root(parent, t);
    if (root_part[size_t(r)] < 0) root_part[size_t(r)] = int(A.parts.size()), A.parts.emplace_back();
    A.tet_part[size_t(t)] = root_part[size_t(r)];
  }
  const size_t np = A.parts.size();
  // Nodes of each part, and the parts of each node.
  std::vector<std::vector<int>> part_nodes(np), node_parts(static_cast<size_t>(nn));
  for (int t : sorted) {
    const int p = A.tet_part[size_t(t)];
    ++A.parts[size_t(p)].tets;
    for (int j = 0; j < 4; ++j) {
      const int v = m.tets(t, j);
      if (v < 0 || v >= nn) fail("anchor_parts: tetrahedron ", t, " refers to node ", v, " of ", nn);
      auto& ps = node_parts[size_t(v)];
      if (std::find(ps.begin(), ps.end(), p) == ps.end()) ps.push_back(p), part_nodes[size_t(p)].push_back(v);
    }
  }
  for (size_t p = 0; p < np; ++p) {
    auto& nodes = part_nodes[p];
    std::sort(nodes.begin(), nodes.end());
    Anchoring::Part& P = A.parts[p];
    P.first_node = nodes.front();
    for (int v : nodes) {
      P.lo = P.lo.cwiseMin(m.node(v)), P.hi = P.hi.cwiseMax(m.node(v));
      P.fixed += node_fixed[size_t(v)] != 0;
    }
  }
  // Anchoring spreads from parts with fixed nodes through shared nodes.
  std::vector<char> node_pinned(size_t(nn), 0);
  for (int v = 0; v < nn; ++v) node_pinned[size_t(v)] = node_fixed[size_t(v)] != 0;
  std::vector<int> queue;
  for (size_t p = 0; p < np; ++p) queue.push_back(int(p));
  while (!queue.empty()) {
    const int p = queue.back();
    queue.pop_back();
    Anchoring::Part& P = A.parts[size_t(p)];
    if (P.anchored) continue;
    std::vector<int> pinned;
    for (int v : part_nodes[size_t(p)])
      if (node_pinned[size_t(v)]) pinned.push_back(v);
    const double tol = 1e-9 * (P.hi - P.lo).norm();
    P.pin = pin_kind(m, pinned, tol, P.pin_a, P.pin_b);
    if (!(P.pin == Anchoring::Pin::none && !pinned.empty())) continue;
    P.anchored = true;
    for (int v : part_nodes[size_t(p)]) {
      node_pinned[size_t(v)] = 1;
      for (int q : node_parts[size_t(v)])
        if (!A.parts[size_t(q)].anchored) queue.push_back(q);
    }
  }
  for (size_t p = 0; p < np; ++p) {
    Anchoring::Part& P = A.parts[p];
    if (P.anchored) continue;
    if (P.pin == Anchoring::Pin::none) P.pin_a = P.pin_b = -1;
    for (int v : {P.pin_a, P.pin_b})
      if (v >= 0 && !node_fixed[size_t(v)]) P.through_shared = true;
  }
  return A;
}

std::string Anchoring::describe(int p) const {
  const Part& P = parts[size_t(p)];
  return cat("the part of the body containing node ", P.first_node, " (", P.tets, " tets, bounding box [", P.lo.x(),
             ", ", P.lo.y(), ", ", P.lo.z(), "] .. [", P.hi.x(), ", ", P.hi.y(), ", ", P.hi.z(), "] m",
             parts.size() > 1 ? cat(", one of ", parts.size(), " parts") : "", ")");
}

std::string Anchoring::why_loose(int p) const {
  const Part& P = parts[size_t(p)];
  switch (P.pin) {
    case Pin::none:
      return "has no fixed node, so it can move freely and the stiffness matrix is singular; fix at least three of "
             "its nodes that are not on one line, or remove those tets";
    case Pin::point:
      return P.through_shared
                 ? cat("hangs by node ", P.pin_a, " alone from the rest of the body (tets that share only a node "
                       "are not joined), so it can turn about that point and the stiffness matrix is singular; "
                       "join it through a face, fix three of its nodes, or remove those tets")
                 : cat("is fixed only at node ", P.pin_a, ", so it can rotate about that point and the stiffness "
                       "matrix is singular; fix at least three of its nodes that are not on one line");
    case Pin::line:
      return P.through_shared
                 ? cat("hangs by the edge through nodes ", P.pin_a, " and ", P.pin_b,
                       " from the rest of the body (tets that share only an edge are not joined), so it can turn "
                       "about that line and the stiffness matrix is singular; join it through a face, fix a node "
                       "of it off that line, or remove those tets")
                 : cat("is fixed only along the line through nodes ", P.pin_a, " and ", P.pin_b,
                       ", so it can rotate about that line and the stiffness matrix is singular; fix a node off "
                       "that line too");
  }
  return "?";
}

}  // namespace softcut::fem
