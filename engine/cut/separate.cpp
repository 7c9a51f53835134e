#include "cut/separate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace softcut::cut::detail {

namespace {

// Snapped nodes on both sides of the blade (and, where strokes cross, nodes
// of the older cut) can leave a few tets cut on every side: a tiny piece
// floating free, singular for the solver and meaningless physically. A group
// of at most kSmallPiece tets, connected through uncut faces, touching
// neither a bigger part nor a locked node, and made only of nodes on some cut
// (a sliver between cut surfaces, not a corner cut off the body), keeps its
// largest cut face instead.
constexpr int kSmallPiece = 32;

// One pass; true if a face was dropped. `cut_keys` (sorted) matches
// `cut_faces`; both are updated.
bool rejoin_small_pieces(const mesh::TetMesh& m, const Adjacency& adj, const CutState& st,
                         std::vector<CutFace>& cut_faces, std::vector<FaceKey>& cut_keys) {
  std::vector<int> seeds, seen;
  for (const auto& c : cut_faces) seeds.insert(seeds.end(), {c.t1, c.t2});
  std::sort(seeds.begin(), seeds.end());
  seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
  std::vector<FaceKey> drop;
  for (int seed : seeds) {
    if (std::binary_search(seen.begin(), seen.end(), seed)) continue;
    std::vector<int> group = {seed}, frontier = {seed};
    bool attached = false, older = false;
    FaceKey best_key{};
    double best_area = -1;
    while (!frontier.empty() && !attached) {
      const int t = frontier.back();
      frontier.pop_back();
      for (int k = 0; k < 4; ++k) {
        attached = attached || st.cut_stroke[size_t(m.tets(t, k))] < 0;
        older = older || st.cut_stroke[size_t(m.tets(t, k))] != st.stroke;
      }
      // Only nodes of this stroke's cut: one swept sheet encloses no volume,
      // so the group is a sliver whatever its size (a sharp V corner can
      // carve one along the whole blade). With an earlier cut it may be a thin
      // piece cut on purpose: only small groups count as slivers.
      attached = attached || (older && int(group.size()) > kSmallPiece);
      for (int f = 0; f < 4 && !attached; ++f) {
        const FaceKey key = face_key(tet_of(m, t), f);
        const int u = neighbour(m, adj, t, key);
        if (std::binary_search(cut_keys.begin(), cut_keys.end(), key)) {
          const double area = (m.node(key[1]) - m.node(key[0])).cross(m.node(key[2]) - m.node(key[0])).norm();
          if (area > best_area) best_area = area, best_key = key;
        } else if (u < 0) {
          // Boundary, or shared with a non-cuttable tet (then it has locked nodes).
          attached = st.locked[size_t(key[0])] || st.locked[size_t(key[1])] || st.locked[size_t(key[2])];
        } else if (std::find(group.begin(), group.end(), u) == group.end()) {
          group.push_back(u);
          frontier.push_back(u);
          attached = older && int(group.size()) > kSmallPiece;
        }
      }
    }
    if (attached) continue;  // the seed's part is big; other seeds in it may still be checked
    seen.insert(seen.end(), group.begin(), group.end());
    std::sort(seen.begin(), seen.end());
    if (best_area >= 0) drop.push_back(best_key);
  }
  if (drop.empty()) return false;
  std::sort(drop.begin(), drop.end());
  cut_faces.erase(std::remove_if(cut_faces.begin(), cut_faces.end(),
                                 [&](const CutFace& c) { return std::binary_search(drop.begin(), drop.end(), c.key); }),
                  cut_faces.end());
  cut_keys.clear();
  for (const auto& c : cut_faces) cut_keys.push_back(c.key);
  return true;
}

}  // namespace

std::vector<CutFace> find_cut_faces(const mesh::TetMesh& m, const Adjacency& adj, const CutState& st,
                                    const std::vector<int>& face_tets, const std::vector<int>& split_tets,
                                    double snap_fraction, int& blocked) {
  const double s = snap_fraction;
  Eigen::Vector3d clo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), chi = -clo;
  double max_edge = 0;
  for (int t : face_tets)
    for (int i = 0; i < 4; ++i) {
      clo = clo.cwiseMin(m.node(m.tets(t, i)));
      chi = chi.cwiseMax(m.node(m.tets(t, i)));
      for (int j = i + 1; j < 4; ++j) max_edge = std::max(max_edge, (m.node(m.tets(t, i)) - m.node(m.tets(t, j))).norm());
    }
  SweptSurface near;  // the part of the accumulated surface that can matter here
  for (const auto& tri : st.swept.triangles)
    if (((tri.rowwise().minCoeff().array() - max_edge) <= chi.array()).all() &&
        ((tri.rowwise().maxCoeff().array() + max_edge) >= clo.array()).all())
      near.triangles.push_back(tri);
  std::vector<CutFace> cut_faces;
  std::vector<FaceKey> blocked_keys;
  for (int t : face_tets) {
    const Tet tt = tet_of(m, t);
    for (int f = 0; f < 4; ++f) {
      const FaceKey key = face_key(tt, f);
      if (!on_stroke(st, key[0]) || !on_stroke(st, key[1]) || !on_stroke(st, key[2])) continue;
      const int other = neighbour(m, adj, t, key);
      if (other < 0) continue;
      const Eigen::Vector3d x0 = m.node(key[0]), x1 = m.node(key[1]), x2 = m.node(key[2]);
      const Eigen::Vector3d centre = (x0 + x1 + x2) / 3;
      const double lf = std::max({(x1 - x0).norm(), (x2 - x0).norm(), (x2 - x1).norm()});
      double tol = 0.5 * s * lf;  // plus how far its nodes were snapped
      for (int v : key) tol = std::max(tol, st.cut_offset[size_t(v)] + 0.5 * s * lf);
      // Where the swept surface folds between the face's nodes (the blade path
      // turns a corner), a flat face through three nodes on it cuts across the
      // corner: its centre lies up to lf/2 sin(theta/2) off the surface, theta
      // the angle between the swept triangles nearest its nodes. No fold (a
      // flat or gently curved cut): nothing changes.
      std::array<int, 3> node_tri = {-1, -1, -1};
      const Eigen::Vector3d xs[3] = {x0, x1, x2};
      for (int k = 0; k < 3; ++k) {
        double dmin = std::numeric_limits<double>::infinity();
        for (size_t i = 0; i < near.triangles.size(); ++i) {
          const double d = point_triangle_distance(xs[k], near.triangles[i]);
          if (d < dmin) dmin = d, node_tri[size_t(k)] = int(i);
        }
      }
      auto tri_normal = [&](int i) {
        const Eigen::Matrix3d& tr = near.triangles[size_t(i)];
        return Eigen::Vector3d((tr.col(1) - tr.col(0)).cross(tr.col(2) - tr.col(0)).normalized());
      };
      double cos_fold = 1;
      for (int a = 0; a < 3; ++a)
        for (int b = a + 1; b < 3; ++b)
          if (node_tri[size_t(a)] >= 0 && node_tri[size_t(b)] >= 0 && node_tri[size_t(a)] != node_tri[size_t(b)])
            cos_fold = std::min(cos_fold, std::abs(tri_normal(node_tri[size_t(a)]).dot(tri_normal(node_tri[size_t(b)]))));
      const bool folded = cos_fold < 1 - 1e-9;
      if (folded) tol += 0.5 * lf * std::sqrt((1 - cos_fold) / 2);
      // The swept triangle it lies on: within reach of its centre and, where
      // cuts cross, the one most parallel to it.
      const Eigen::Vector3d nf = (x1 - x0).cross(x2 - x0).normalized();
      int near_tri = -1;
      double best = -1;
      for (size_t i = 0; i < near.triangles.size(); ++i) {
        const Eigen::Matrix3d& tri = near.triangles[i];
        if (point_triangle_distance(centre, tri) > tol) continue;
        const double align = std::abs(nf.dot((tri.col(1) - tri.col(0)).cross(tri.col(2) - tri.col(0)).normalized()));
        if (align > best) best = align, near_tri = int(i);
      }
      if (near_tri < 0) continue;
      // Sides by that triangle's plane: each tet sits on the side of its
      // farthest node off the cut (snapped nodes count as on it, wherever
      // they lie), or of its farthest node when all are on it.
      auto side = [&](int tet, int tri_id) {
        const Eigen::Matrix3d& tri = near.triangles[size_t(tri_id)];
        const Eigen::Vector3d n = tri_normal(tri_id);
        double far = 0, far_off = 0;
        for (int k = 0; k < 4; ++k) {
          const int v = m.tets(tet, k);
          const double d = n.dot(m.node(v) - tri.col(0));
          if (std::abs(d) > std::abs(far)) far = d;
          if (!on_stroke(st, v) && std::abs(d) > std::abs(far_off)) far_off = d;
        }
        if (far_off != 0) far = far_off;
        return std::abs(far) <= 1e-12 * lf ? 0 : far > 0 ? 1 : -1;
      };
      auto opposite = [&](int tri_id) {
        const int st1 = side(t, tri_id), st2 = side(other, tri_id);
        return st1 != 0 && st2 != 0 && st1 != st2;
      };
      // At a fold one leg's plane, extended past the corner, can put both
      // tets on one side: there the planes of the legs at the face's nodes
      // are asked too.
      // So can the triangle picked for the face when it is not on the leg of
      // its nodes (a snapped node's offset widens the reach past a corner to
      // another leg, or to the chord a step swept across the corner, and that
      // one may be the best aligned).
      bool fold_here = folded;
      for (int k = 0; k < 3; ++k)
        fold_here = fold_here || (node_tri[size_t(k)] >= 0 && node_tri[size_t(k)] != near_tri &&
                                  std::abs(tri_normal(node_tri[size_t(k)]).dot(tri_normal(near_tri))) < 1 - 1e-9);
      bool split_by_cut = opposite(near_tri);
      for (int k = 0; k < 3 && fold_here && !split_by_cut; ++k) split_by_cut = opposite(node_tri[size_t(k)]);
      if (!split_by_cut) continue;
      if (st.locked[size_t(key[0])] || st.locked[size_t(key[1])] || st.locked[size_t(key[2])]) {
        blocked_keys.push_back(key);
        continue;
      }
      cut_faces.push_back({key, std::min(t, other), std::max(t, other)});
    }
  }
  std::sort(blocked_keys.begin(), blocked_keys.end());
  blocked = int(std::unique(blocked_keys.begin(), blocked_keys.end()) - blocked_keys.begin());
  for (const auto& p : st.pending) {
    if (std::binary_search(split_tets.begin(), split_tets.end(), p[0]) ||
        std::binary_search(split_tets.begin(), split_tets.end(), p[1]))
      continue;
    FaceKey key;
    if (shared_nodes(tet_of(m, p[0]), tet_of(m, p[1]), key) == 3) cut_faces.push_back({key, p[0], p[1]});
  }
  std::sort(cut_faces.begin(), cut_faces.end(),
            [](const CutFace& a, const CutFace& b) { return a.key < b.key; });
  cut_faces.erase(std::unique(cut_faces.begin(), cut_faces.end(),
                              [](const CutFace& a, const CutFace& b) { return a.key == b.key; }),
                  cut_faces.end());
  std::vector<FaceKey> cut_keys;
  for (const auto& c : cut_faces) cut_keys.push_back(c.key);
  while (rejoin_small_pieces(m, adj, st, cut_faces, cut_keys)) {
  }
  return cut_faces;
}

std::vector<int> separate(mesh::TetMesh& m, const Adjacency& adj, CutState& st, const std::vector<CutFace>& cut_faces,
                          CutRecord& rec) {
  // The tets around a node on a cut face fall into groups
  // connected through uncut faces; every group but the first gets a copy.
  const int n0 = rec.nodes_before, n1 = m.num_nodes();
  std::vector<FaceKey> cut_keys;
  for (const auto& c : cut_faces) cut_keys.push_back(c.key);
  std::vector<int> cut_nodes;
  for (const auto& k : cut_keys) cut_nodes.insert(cut_nodes.end(), k.begin(), k.end());
  std::sort(cut_nodes.begin(), cut_nodes.end());
  cut_nodes.erase(std::unique(cut_nodes.begin(), cut_nodes.end()), cut_nodes.end());
  struct Relabel {
    int tet, from, to;
  };
  std::vector<Relabel> relabel;
  std::vector<int> dup_source;  // node each copy duplicates
  int next_node = n1;
  for (int v : cut_nodes) {
    const std::vector<int> star(adj.begin(v), adj.end(v));
    std::vector<int> root(star.size());
    std::iota(root.begin(), root.end(), 0);
    auto find = [&](int i) {
      while (root[size_t(i)] != i) i = root[size_t(i)] = root[size_t(root[size_t(i)])];
      return i;
    };
    for (size_t i = 0; i < star.size(); ++i)
      for (size_t j = i + 1; j < star.size(); ++j) {
        FaceKey key;
        if (shared_nodes(tet_of(m, star[i]), tet_of(m, star[j]), key) != 3) continue;
        if (std::binary_search(cut_keys.begin(), cut_keys.end(), key)) continue;
        const int a = find(int(i)), b = find(int(j));
        root[size_t(std::max(a, b))] = std::min(a, b);  // smallest index is the root
      }
    std::vector<int> copy_of_root(star.size(), -1);
    for (size_t i = 0; i < star.size(); ++i) {
      const int r = find(int(i));
      if (r == find(0)) continue;
      if (copy_of_root[size_t(r)] < 0) {
        copy_of_root[size_t(r)] = next_node++;
        NewNode nn{copy_of_root[size_t(r)], {v, -1}, {1, 0}, true};
        if (v >= n0) {
          nn.parent = rec.new_nodes[size_t(v - n0)].parent;
          nn.weight = rec.new_nodes[size_t(v - n0)].weight;
        }
        rec.new_nodes.push_back(nn);
        dup_source.push_back(v);
      }
      relabel.push_back({star[i], v, copy_of_root[size_t(r)]});
    }
  }
  m.nodes.conservativeResize(next_node, 3);
  for (size_t i = 0; i < dup_source.size(); ++i) m.nodes.row(n1 + Eigen::Index(i)) = m.nodes.row(dup_source[i]);
  st.locked.resize(size_t(next_node), 0);
  for (int v : dup_source) {
    st.cut_stroke.push_back(st.cut_stroke[size_t(v)]);
    st.cut_offset.push_back(st.cut_offset[size_t(v)]);
  }
  std::vector<int> changed;
  for (const Relabel& r : relabel) {
    for (int k = 0; k < 4; ++k)
      if (m.tets(r.tet, k) == r.from) m.tets(r.tet, k) = r.to;
    changed.push_back(r.tet);
  }

  // Faces still joined stay pending (the cut front).
  st.pending.clear();
  for (const auto& c : cut_faces) {
    FaceKey key;
    if (shared_nodes(tet_of(m, c.t1), tet_of(m, c.t2), key) == 3) st.pending.push_back({c.t1, c.t2});
    else ++rec.faces_separated;
  }
  rec.faces_pending = int(st.pending.size());
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  return changed;
}

}  // namespace softcut::cut::detail
