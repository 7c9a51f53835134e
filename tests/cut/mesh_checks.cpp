#include "mesh_checks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <numeric>

#include "cut/tet_quality.hpp"

namespace softcut::test {

namespace {

struct FaceUse {
  std::array<int, 3> key;
  int tet, local;
};

std::vector<FaceUse> face_uses(const mesh::TetMesh& m) {
  std::vector<FaceUse> f;
  for (int t = 0; t < m.num_tets(); ++t)
    for (int l = 0; l < 4; ++l) {
      std::array<int, 3> k = {m.tets(t, mesh::kTetFaces[l][0]), m.tets(t, mesh::kTetFaces[l][1]),
                              m.tets(t, mesh::kTetFaces[l][2])};
      std::sort(k.begin(), k.end());
      f.push_back({k, t, l});
    }
  std::sort(f.begin(), f.end(), [](const FaceUse& a, const FaceUse& b) {
    return a.key != b.key ? a.key < b.key : a.tet < b.tet;
  });
  return f;
}

}  // namespace

MeshCheck check_mesh(const mesh::TetMesh& m, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  MeshCheck c;
  const double scale = (hi - lo).norm();
  for (int t = 0; t < m.num_tets(); ++t) {
    const double v = mesh::signed_volume(m, t);
    c.volume += v;
    double l = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) l = std::max(l, (m.node(m.tets(t, i)) - m.node(m.tets(t, j))).norm());
    if (!(v > mesh::kDegenerateVolume * l * l * l)) ++c.inverted;
    c.worst_dihedral = std::min(c.worst_dihedral, cut::min_dihedral_deg(m, t));
  }
  const auto uses = face_uses(m);
  // Boundary faces as sorted position triples (rounded to a grid far below
  // any edge length) with their orientation sign.
  struct Geo {
    std::array<std::array<long long, 3>, 3> p;
    Eigen::Vector3d normal;
  };
  std::vector<Geo> boundary;
  std::vector<std::array<int, 2>> directed;  // boundary face edges, as used
  for (size_t i = 0; i < uses.size();) {
    size_t j = i + 1;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    if (j - i > 2) ++c.faces_over_two;
    if (j - i == 1) {
      const int t = uses[i].tet, l = uses[i].local;
      Eigen::Vector3d x[3];
      for (int k = 0; k < 3; ++k) x[k] = m.node(m.tets(t, mesh::kTetFaces[l][k]));
      for (int k = 0; k < 3; ++k)
        directed.push_back({m.tets(t, mesh::kTetFaces[l][k]), m.tets(t, mesh::kTetFaces[l][(k + 1) % 3])});
      bool on_box = false;
      for (int a = 0; a < 3; ++a)
        for (double plane : {lo(a), hi(a)}) {
          bool all = true;
          for (int k = 0; k < 3; ++k) all = all && std::abs(x[k](a) - plane) <= 1e-12 * scale;
          on_box = on_box || all;
        }
      if (!on_box) {
        Geo g;
        for (int k = 0; k < 3; ++k)
          for (int a = 0; a < 3; ++a) g.p[size_t(k)][size_t(a)] = std::llround(x[k](a) / scale * 1e9);
        std::sort(g.p.begin(), g.p.end());
        g.normal = (x[1] - x[0]).cross(x[2] - x[0]);
        boundary.push_back(g);
      }
    }
    i = j;
  }
  std::vector<std::array<int, 2>> reversed;
  for (const auto& e : directed) reversed.push_back({e[1], e[0]});
  std::sort(directed.begin(), directed.end());
  std::sort(reversed.begin(), reversed.end());
  std::vector<std::array<int, 2>> odd;
  std::set_symmetric_difference(directed.begin(), directed.end(), reversed.begin(), reversed.end(),
                                std::back_inserter(odd));
  c.open_edges = int(odd.size());
  // Hanging nodes: boundary faces against the nodes of the same piece, with
  // nodes sorted by x to visit only those within a face's x-range.
  std::vector<int> comp;
  components(m, &comp);
  std::vector<int> node_comp(size_t(m.num_nodes()), -1);
  for (int t = 0; t < m.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) node_comp[size_t(m.tets(t, k))] = comp[size_t(t)];
  std::vector<int> by_x(size_t(m.num_nodes()));
  std::iota(by_x.begin(), by_x.end(), 0);
  std::sort(by_x.begin(), by_x.end(), [&](int a, int b) { return m.nodes(a, 0) < m.nodes(b, 0); });
  const double eps = 1e-9 * scale;
  std::vector<char> hanging(size_t(m.num_nodes()), 0);
  for (size_t i = 0; i < uses.size(); ++i) {
    const bool single = (i == 0 || uses[i - 1].key != uses[i].key) &&
                        (i + 1 == uses.size() || uses[i + 1].key != uses[i].key);
    if (!single) continue;
    const auto& k = uses[i].key;
    const Eigen::Vector3d a = m.node(k[0]), b = m.node(k[1]), c3 = m.node(k[2]);
    const Eigen::Vector3d lo3 = a.cwiseMin(b).cwiseMin(c3), hi3 = a.cwiseMax(b).cwiseMax(c3);
    const Eigen::Vector3d n = (b - a).cross(c3 - a);
    const double area2 = n.norm();
    auto first = std::lower_bound(by_x.begin(), by_x.end(), lo3(0) - eps,
                                  [&](int v, double x) { return m.nodes(v, 0) < x; });
    for (auto it = first; it != by_x.end() && m.nodes(*it, 0) <= hi3(0) + eps; ++it) {
      const int v = *it;
      if (v == k[0] || v == k[1] || v == k[2] || node_comp[size_t(v)] != comp[size_t(uses[i].tet)]) continue;
      const Eigen::Vector3d x = m.node(v);
      if (((x - lo3).array() < -eps).any() || ((x - hi3).array() > eps).any()) continue;
      if (std::abs(n.dot(x - a)) > eps * std::sqrt(area2)) continue;  // off the face plane
      // Barycentric coordinates in the face; a copy of a vertex sits at one of them.
      const double wa = (b - x).cross(c3 - x).dot(n) / (area2 * area2);
      const double wb = (c3 - x).cross(a - x).dot(n) / (area2 * area2);
      const double wc = 1 - wa - wb;
      const double tol = 1e-9;
      const bool at_vertex = (wa > 1 - tol) || (wb > 1 - tol) || (wc > 1 - tol);
      if (!at_vertex && wa > -tol && wb > -tol && wc > -tol) hanging[size_t(v)] = 1;
    }
  }
  for (char h : hanging) c.hanging_nodes += h;
  std::vector<size_t> order(boundary.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return boundary[a].p < boundary[b].p; });
  for (size_t i = 0; i < order.size();) {
    size_t j = i + 1;
    while (j < order.size() && boundary[order[j]].p == boundary[order[i]].p) ++j;
    const bool twin = j - i == 2 && boundary[order[i]].normal.dot(boundary[order[i + 1]].normal) < 0;
    if (!twin) c.unmatched_boundary += int(j - i);
    i = j;
  }
  return c;
}

int components(const mesh::TetMesh& m, std::vector<int>* comp_out) {
  std::vector<int> root(size_t(m.num_tets()));
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](int i) {
    while (root[size_t(i)] != i) i = root[size_t(i)] = root[size_t(root[size_t(i)])];
    return i;
  };
  const auto uses = face_uses(m);
  for (size_t i = 0; i + 1 < uses.size(); ++i)
    if (uses[i].key == uses[i + 1].key) root[size_t(find(uses[i].tet))] = find(uses[i + 1].tet);
  std::vector<int> id(size_t(m.num_tets()), -1), comp(size_t(m.num_tets()));
  int n = 0;
  for (int t = 0; t < m.num_tets(); ++t) {
    const int r = find(t);
    if (id[size_t(r)] < 0) id[size_t(r)] = n++;
    comp[size_t(t)] = id[size_t(r)];
  }
  if (comp_out) *comp_out = comp;
  return n;
}

}  // namespace softcut::test
