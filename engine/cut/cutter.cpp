#include "cut/cutter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/error.hpp"
#include "core/warning.hpp"
#include "cut/separate.hpp"
#include "cut/tet_quality.hpp"

namespace softcut::cut {

using namespace detail;

namespace {

struct Crossing {
  int a, b;  // edge end nodes, a < b
  double t;  // crossing at (1 - t) x_a + t x_b
};

struct LocalTet {
  Tet v;
  int parent;  // pre-step tet id
};

// Bisect every local tet containing each split edge, in split order. Split k
// creates node first_new + k. Children of one bisection never contain the
// split edge again, so one pass per split suffices.
void bisect(const std::vector<Crossing>& splits, int first_new, std::vector<LocalTet>& local) {
  for (size_t k = 0; k < splits.size(); ++k) {
    const int a = splits[k].a, b = splits[k].b, p = first_new + int(k);
    const size_t n = local.size();
    for (size_t i = 0; i < n; ++i) {
      if (!contains(local[i].v, a) || !contains(local[i].v, b)) continue;
      LocalTet other = local[i];
      for (int& x : local[i].v)
        if (x == a) x = p;
      for (int& x : other.v)
        if (x == b) x = p;
      local.push_back(other);
    }
  }
}

}  // namespace

CutState make_cut_state(const mesh::TetMesh& m, std::vector<char> cuttable, std::vector<char> locked) {
  if (cuttable.size() != size_t(m.num_tets()))
    fail("cut: cuttable mask has ", cuttable.size(), " entries but the mesh has ", m.num_tets(),
         " tetrahedra; pass one entry per tet");
  if (locked.size() != size_t(m.num_nodes()))
    fail("cut: locked mask has ", locked.size(), " entries but the mesh has ", m.num_nodes(),
         " nodes; pass one entry per node");
  CutState s;
  s.cuttable = std::move(cuttable);
  s.locked = std::move(locked);
  for (int t = 0; t < m.num_tets(); ++t)
    if (!s.cuttable[size_t(t)])
      for (int k = 0; k < 4; ++k) s.locked[size_t(m.tets(t, k))] = 1;
  s.cut_stroke.assign(size_t(m.num_nodes()), -1);
  s.quality.assign(size_t(m.num_tets()), 180);
  for (int t = 0; t < m.num_tets(); ++t)
    if (s.cuttable[size_t(t)]) s.quality[size_t(t)] = min_dihedral_deg(m, t);
  s.cut_offset.assign(size_t(m.num_nodes()), 0);
  return s;
}

void begin_stroke(CutState& st) {
  ++st.stroke;
  st.swept.triangles.clear();
}

CutRecord cut_step(mesh::TetMesh& m, CutState& st, const SweptSurface& blade, const CutOptions& opt) {
  if (!(opt.snap_fraction > 0 && opt.snap_fraction < 0.5))
    fail("cut: snap_fraction must lie in (0, 0.5), got ", opt.snap_fraction);
  if (!(opt.min_dihedral_deg >= 0 && opt.min_dihedral_deg < 60))
    fail("cut: min_dihedral_deg must lie in [0, 60), got ", opt.min_dihedral_deg);
  const int n0 = m.num_nodes(), t0 = m.num_tets();
  if (st.cuttable.size() != size_t(t0) || st.quality.size() != size_t(t0) || st.locked.size() != size_t(n0) ||
      st.cut_stroke.size() != size_t(n0) || st.cut_offset.size() != size_t(n0))
    fail("cut: state does not match the mesh (", st.cuttable.size(), " tets / ", st.locked.size(),
         " nodes in the state, ", t0, " / ", n0, " in the mesh); build it with make_cut_state and "
         "pass the same mesh to every step");
  if (m.labels.size() != t0) fail("cut: mesh has ", m.labels.size(), " labels for ", t0, " tets");
  for (size_t i = 0; i < blade.triangles.size(); ++i)
    if (!blade.triangles[i].allFinite())
      fail("cut: blade triangle ", i, " has a non-finite coordinate; check the scalpel pose");
  // Nodes of non-cuttable tets stay locked even if a caller edited the masks:
  // then no edge of a non-cuttable tet is ever split.
  for (int t = 0; t < t0; ++t)
    if (!st.cuttable[size_t(t)])
      for (int k = 0; k < 4; ++k) st.locked[size_t(m.tets(t, k))] = 1;
  const double s = opt.snap_fraction;
  auto current = [&](int v) { return on_stroke(st, v); };

  CutRecord rec;
  rec.nodes_before = n0;
  rec.tets_before = t0;
  rec.tet_parent.resize(size_t(t0));
  std::iota(rec.tet_parent.begin(), rec.tet_parent.end(), 0);

  // 1. Candidate tets: cuttable tets near the blade.
  Eigen::Vector3d lo, hi;
  bounds(blade, lo, hi);
  std::vector<int> cand;
  std::vector<Eigen::Vector3d> blade_normal;
  for (const auto& tri : blade.triangles)
    blade_normal.push_back((tri.col(1) - tri.col(0)).cross(tri.col(2) - tri.col(0)).normalized());
  std::vector<int> uncuttable;  // near the blade but not cuttable: counted, never cut
  for (int t = 0; t < t0 && !blade.triangles.empty(); ++t) {
    Eigen::Vector3d tlo = m.node(m.tets(t, 0)), thi = tlo;
    for (int k = 1; k < 4; ++k) {
      tlo = tlo.cwiseMin(m.node(m.tets(t, k)));
      thi = thi.cwiseMax(m.node(m.tets(t, k)));
    }
    const double pad = s * (thi - tlo).norm();
    if (!(((tlo.array() - pad) <= hi.array()).all() && ((thi.array() + pad) >= lo.array()).all())) continue;
    // Near the plane of some blade triangle (box-plane overlap test).
    const Eigen::Vector3d centre = (tlo + thi) / 2, half = (thi - tlo) / 2;
    for (size_t i = 0; i < blade.triangles.size(); ++i)
      if (std::abs(blade_normal[i].dot(centre - blade.triangles[i].col(0))) <=
          blade_normal[i].cwiseAbs().dot(half) + pad) {
        (st.cuttable[size_t(t)] ? cand : uncuttable).push_back(t);
        break;
      }
  }
  // A blade that reaches tissue it may not cut (sim: the nonoperational
  // region) says so: the caller warns when that is all it reached.
  for (int t : uncuttable) {
    bool crossed = false;
    for (int i = 0; i < 4 && !crossed; ++i)
      for (int j = i + 1; j < 4 && !crossed; ++j)
        crossed = segment_crossing(blade, m.node(m.tets(t, i)), m.node(m.tets(t, j))) >= 0;
    rec.uncuttable_tets_crossed += crossed;
  }

  // 2. Edges of the candidates, their blade crossings, shortest edge per node.
  std::vector<std::array<int, 2>> edges;
  for (int t : cand)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        edges.push_back({std::min(m.tets(t, i), m.tets(t, j)), std::max(m.tets(t, i), m.tets(t, j))});
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<double> min_len(size_t(n0), std::numeric_limits<double>::infinity());
  std::vector<Crossing> hits;
  for (const auto& e : edges) {
    const Eigen::Vector3d xa = m.node(e[0]), xb = m.node(e[1]);
    const double len = (xb - xa).norm();
    min_len[size_t(e[0])] = std::min(min_len[size_t(e[0])], len);
    min_len[size_t(e[1])] = std::min(min_len[size_t(e[1])], len);
    const double t = segment_crossing(blade, xa, xb);
    if (t >= 0) hits.push_back({e[0], e[1], t});
  }
  std::vector<int> near_nodes;  // nodes within snapping distance of the blade itself
  for (const auto& e : edges)
    for (int v : e) near_nodes.push_back(v);
  std::sort(near_nodes.begin(), near_nodes.end());
  near_nodes.erase(std::unique(near_nodes.begin(), near_nodes.end()), near_nodes.end());
  // A node already on the cut stays there for a blade passing it again as
  // far as it was when it joined (a snap vetoed for quality may be far); not
  // farther: adding the reach to that offset let each step drag the node
  // along (the offset grew by the reach every step).
  near_nodes.erase(std::remove_if(near_nodes.begin(), near_nodes.end(),
                                  [&](int v) {
                                    const double d = distance(blade, m.node(v));
                                    const double reach = s * min_len[size_t(v)];
                                    return d > std::max(reach, current(v) ? st.cut_offset[size_t(v)] : 0.0);
                                  }),
                   near_nodes.end());

  // 3. Plan: snap or split each crossing; veto splits whose children would be
  // slivers (snap them to the nearer end instead) until every child is good.
  Adjacency adj;
  adj.build(m, st.cuttable);
  auto pos = [&](int v, const std::vector<Crossing>& splits) -> Eigen::Vector3d {
    if (v < n0) return m.node(v);
    const Crossing& c = splits[size_t(v - n0)];
    return (1 - c.t) * m.node(c.a) + c.t * m.node(c.b);
  };
  std::vector<char> veto(hits.size(), 0), snapped(size_t(n0), 0);
  std::vector<Crossing> splits;
  std::vector<int> split_hit;  // hit index of each split
  std::vector<LocalTet> local;
  int locked_edges = 0;
  for (;;) {
    std::fill(snapped.begin(), snapped.end(), 0);
    for (int v : near_nodes) snapped[size_t(v)] = 1;
    for (size_t h = 0; h < hits.size(); ++h) {
      const Crossing& c = hits[h];
      if (veto[h]) snapped[size_t(c.t < 0.5 ? c.a : c.b)] = 1;
      else if (c.t < s) snapped[size_t(c.a)] = 1;
      else if (c.t > 1 - s) snapped[size_t(c.b)] = 1;
    }
    splits.clear();
    split_hit.clear();
    locked_edges = 0;
    for (size_t h = 0; h < hits.size(); ++h) {
      const Crossing& c = hits[h];
      if (veto[h] || snapped[size_t(c.a)] || snapped[size_t(c.b)]) continue;
      if (st.locked[size_t(c.a)] && st.locked[size_t(c.b)]) {
        ++locked_edges;  // may be an edge of a non-cuttable tet: never split
        continue;
      }
      splits.push_back(c);
      split_hit.push_back(int(h));
    }
    // Tets around the split edges, bisected in split order.
    std::vector<int> roots;
    for (const Crossing& c : splits)
      std::set_intersection(adj.begin(c.a), adj.end(c.a), adj.begin(c.b), adj.end(c.b),
                            std::back_inserter(roots));
    std::sort(roots.begin(), roots.end());
    roots.erase(std::unique(roots.begin(), roots.end()), roots.end());
    local.clear();
    for (int t : roots) local.push_back({tet_of(m, t), t});
    bisect(splits, n0, local);
    bool bad = false;
    std::vector<double> parent_q;
    for (int t : roots) parent_q.push_back(st.quality[size_t(t)]);
    for (const LocalTet& lt : local) {
      const double q = min_dihedral_deg(pos(lt.v[0], splits), pos(lt.v[1], splits), pos(lt.v[2], splits),
                                        pos(lt.v[3], splits));
      const size_t r = size_t(std::lower_bound(roots.begin(), roots.end(), lt.parent) - roots.begin());
      if (q >= std::min(opt.min_dihedral_deg, parent_q[r])) continue;
      // Veto the split of this child whose crossing lies nearest an edge end.
      int worst = -1;
      double worst_margin = 1;
      for (int v : lt.v)
        if (v >= n0) {
          const double t = splits[size_t(v - n0)].t, margin = std::min(t, 1 - t);
          if (margin < worst_margin) worst_margin = margin, worst = v;
        }
      if (worst >= 0 && !veto[size_t(split_hit[size_t(worst - n0)])]) {
        veto[size_t(split_hit[size_t(worst - n0)])] = 1;
        ++rec.splits_vetoed;
        bad = true;
      }
    }
    if (!bad) break;
  }

  // 4. Commit splits: new nodes appended, first child of a tet keeps its slot.
  const int nsplit = int(splits.size());
  m.nodes.conservativeResize(n0 + nsplit, 3);
  for (int k = 0; k < nsplit; ++k) {
    const Crossing& c = splits[size_t(k)];
    m.nodes.row(n0 + k) = pos(n0 + k, splits).transpose();
    rec.new_nodes.push_back({n0 + k, {c.a, c.b}, {1 - c.t, c.t}, false});
  }
  st.locked.resize(size_t(n0 + nsplit), 0);
  st.cut_stroke.resize(size_t(n0 + nsplit), st.stroke);
  st.cut_offset.resize(size_t(n0 + nsplit), 0);
  for (int v = 0; v < n0; ++v)
    if (snapped[size_t(v)]) {
      if (st.locked[size_t(v)]) {  // never cut: the caller says the cut stopped short
        ++rec.locked_snapped;
        rec.locked_snap_reach = std::max(rec.locked_snap_reach, s * min_len[size_t(v)]);
      }
      rec.nodes_snapped += st.cut_stroke[size_t(v)] < 0;
      st.cut_offset[size_t(v)] = std::max(current(v) ? st.cut_offset[size_t(v)] : 0.0, distance(blade, m.node(v)));
      st.cut_stroke[size_t(v)] = st.stroke;
    }
  std::stable_sort(local.begin(), local.end(),
                   [](const LocalTet& a, const LocalTet& b) { return a.parent < b.parent; });
  std::vector<int> children;
  {
    int added = 0;
    for (size_t i = 0; i < local.size(); ++i) added += (i > 0 && local[i].parent == local[i - 1].parent);
    m.tets.conservativeResize(t0 + added, 4);
    m.labels.conservativeResize(t0 + added);
    int next = t0;
    for (size_t i = 0; i < local.size(); ++i) {
      const bool first = i == 0 || local[i].parent != local[i - 1].parent;
      const int id = first ? local[i].parent : next++;
      if (first) rec.split_tets.push_back(local[i].parent);
      for (int k = 0; k < 4; ++k) m.tets(id, k) = local[i].v[size_t(k)];
      m.labels(id) = m.labels(local[i].parent);
      if (!first) {
        st.cuttable.push_back(1);
        rec.tet_parent.push_back(local[i].parent);
      }
      children.push_back(id);
    }
  }
  rec.edges_split = nsplit;
  st.quality.resize(st.cuttable.size(), 180);
  for (int id : children) {
    st.quality[size_t(id)] = min_dihedral_deg(m, id);
    rec.worst_new_dihedral_deg = std::min(rec.worst_new_dihedral_deg, st.quality[size_t(id)]);
  }
  append(st.swept, blade);
  adj.build(m, st.cuttable);

  // 5-7. Faces on the cut, their separation, the cut front left pending.
  std::vector<int> face_tets = cand;
  face_tets.insert(face_tets.end(), children.begin(), children.end());
  // A node snapped onto the cut (a vetoed split may snap one far from this
  // step's blade) completes faces in tets that are not candidates now.
  for (int v = 0; v < n0; ++v)
    if (snapped[size_t(v)]) face_tets.insert(face_tets.end(), adj.begin(v), adj.end(v));
  std::sort(face_tets.begin(), face_tets.end());
  face_tets.erase(std::unique(face_tets.begin(), face_tets.end()), face_tets.end());
  int blocked = 0;
  const std::vector<CutFace> cut_faces = find_cut_faces(m, adj, st, face_tets, rec.split_tets, s, blocked);
  std::vector<int> changed = separate(m, adj, st, cut_faces, rec);
  changed.insert(changed.end(), children.begin(), children.end());
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  rec.changed_tets = std::move(changed);
  rec.faces_pending = int(st.pending.size());
  for (int t = 0; t < m.num_tets(); ++t)
    if (st.cuttable[size_t(t)]) rec.worst_dihedral_deg = std::min(rec.worst_dihedral_deg, st.quality[size_t(t)]);
  if (locked_edges > 0 || blocked > 0)
    rec.warnings.push_back(coded_warning("cut_at_interface", cat("cut reached the locked interface: ", blocked,
                                         " face(s) with locked nodes kept joined and ", locked_edges,
                                         " edge(s) between locked nodes not split; the cut stops there")));
  return rec;
}

Eigen::MatrixX3d map_node_field(const CutRecord& rec, const Eigen::MatrixX3d& before) {
  if (before.rows() != rec.nodes_before)
    fail("cut: field has ", before.rows(), " rows but the mesh had ", rec.nodes_before, " nodes before the cut");
  Eigen::MatrixX3d after(rec.nodes_before + Eigen::Index(rec.new_nodes.size()), 3);
  after.topRows(rec.nodes_before) = before;
  for (const NewNode& nn : rec.new_nodes) {
    after.row(nn.id) = nn.weight[0] * before.row(nn.parent[0]);
    if (nn.parent[1] >= 0) after.row(nn.id) += nn.weight[1] * before.row(nn.parent[1]);
  }
  return after;
}

}  // namespace softcut::cut
