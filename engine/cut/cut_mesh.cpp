#include "cut/cut_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>

namespace softcut::cut {

namespace {

using FaceKey = std::array<int, 3>;

FaceKey sorted_face(int a, int b, int c) {
  FaceKey k = {a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

FaceKey local_face(const mesh::TetMesh& m, int t, int lf) {
  return sorted_face(m.tets(t, mesh::kTetFaces[lf][0]), m.tets(t, mesh::kTetFaces[lf][1]),
                     m.tets(t, mesh::kTetFaces[lf][2]));
}

}  // namespace

CutMesh initial_cut_mesh(const RestBody& rest) {
  CutMesh cm;
  cm.mesh = rest.mesh;
  cm.surface = rest.surface;
  cm.tet_material = rest.tet_material;
  cm.operational_tet = rest.operational_tet;
  cm.node_clamped.assign(size_t(rest.mesh.num_nodes()), 0);
  for (int n : rest.fixed) cm.node_clamped[size_t(n)] = 1;
  cm.node_fixed = cm.node_clamped;
  cm.node_held.assign(size_t(rest.mesh.num_nodes()), 0);
  cm.held_displacement = Eigen::MatrixX3d::Zero(rest.mesh.num_nodes(), 3);
  cm.tet_detached.assign(size_t(rest.mesh.num_tets()), 0);
  cm.cut_face.assign(size_t(4 * rest.mesh.num_tets()), 0);
  cm.origin_tet.resize(size_t(rest.mesh.num_tets()));
  std::iota(cm.origin_tet.begin(), cm.origin_tet.end(), 0);
  std::vector<char> locked(size_t(rest.mesh.num_nodes()), 0);
  for (int n : rest.interface) locked[size_t(n)] = 1;  // make_cut_state adds nodes of nonoperational tets
  cm.cut = make_cut_state(cm.mesh, cm.operational_tet, std::move(locked));
  return cm;
}

void update_after_cut(const RestBody& rest, CutMesh& cm, const CutRecord& rec) {
  const int nt = cm.mesh.num_tets(), nn = cm.mesh.num_nodes();
  std::vector<fem::Material> mat(static_cast<size_t>(nt));
  std::vector<char> op(static_cast<size_t>(nt));
  for (int t = 0; t < nt; ++t) {
    const int parent = rec.tet_parent[size_t(t)];
    mat[size_t(t)] = cm.tet_material[size_t(parent)];
    op[size_t(t)] = cm.operational_tet[size_t(parent)];
  }
  std::vector<int> origin(static_cast<size_t>(nt));
  for (int t = 0; t < nt; ++t) origin[size_t(t)] = cm.origin_tet[size_t(rec.tet_parent[size_t(t)])];
  cm.tet_material = std::move(mat);
  cm.operational_tet = std::move(op);
  cm.origin_tet = std::move(origin);
  cm.node_clamped.resize(size_t(nn), 0);
  for (const NewNode& v : rec.new_nodes) {
    bool fixed = true;  // fixed when every contributing parent is (a clamp stays a clamp)
    for (int k = 0; k < 2; ++k)
      if (v.parent[size_t(k)] >= 0 && v.weight[size_t(k)] != 0)
        fixed &= cm.node_clamped[size_t(v.parent[size_t(k)])] != 0;
    cm.node_clamped[size_t(v.id)] = fixed;
  }
  // Cut faces: boundary faces that do not lie on a rest boundary face of the
  // rest tet they come from (children of split outer faces stay outer faces).
  cm.surface = mesh::extract_surface(cm.mesh);
  std::map<int, std::vector<int>> rest_faces;  // rest tet -> its local faces on the rest boundary
  for (Eigen::Index f = 0; f < rest.surface.faces.rows(); ++f) {
    const int t = rest.surface.face_tet(f);
    const FaceKey key = sorted_face(rest.surface.faces(f, 0), rest.surface.faces(f, 1), rest.surface.faces(f, 2));
    for (int lf = 0; lf < 4; ++lf)
      if (local_face(rest.mesh, t, lf) == key) rest_faces[t].push_back(lf);
  }
  cm.cut_face.assign(size_t(4 * nt), 0);
  for (Eigen::Index f = 0; f < cm.surface.faces.rows(); ++f) {
    const int t = cm.surface.face_tet(f);
    const FaceKey key = sorted_face(cm.surface.faces(f, 0), cm.surface.faces(f, 1), cm.surface.faces(f, 2));
    bool outer = false;
    const auto it = rest_faces.find(cm.origin_tet[size_t(t)]);
    if (it != rest_faces.end())
      for (int lf : it->second) {
        const int T = it->first;
        const Eigen::Vector3d p = rest.mesh.node(rest.mesh.tets(T, mesh::kTetFaces[lf][0]));
        const Eigen::Vector3d q = rest.mesh.node(rest.mesh.tets(T, mesh::kTetFaces[lf][1]));
        const Eigen::Vector3d r = rest.mesh.node(rest.mesh.tets(T, mesh::kTetFaces[lf][2]));
        const Eigen::Vector3d n = (q - p).cross(r - p);
        const double tol = 1e-9 * n.norm() * std::max({(q - p).norm(), (r - p).norm(), 1e-300});
        bool on = true;
        for (int v : key) on &= std::abs(n.dot(cm.mesh.node(v) - p)) <= tol;
        outer |= on;
      }
    if (outer) continue;
    for (int lf = 0; lf < 4; ++lf)
      if (local_face(cm.mesh, t, lf) == key) cm.cut_face[size_t(4 * t + lf)] = 1;
  }
}

std::vector<DetachedPiece> update_detached(CutMesh& cm, const CutRecord& rec, const Eigen::MatrixX3d& u) {
  const int nn = cm.mesh.num_nodes(), nt = cm.mesh.num_tets();
  const std::vector<char> was_detached = std::move(cm.tet_detached);  // (pre-step ntet)
  const std::vector<char> was_held = std::move(cm.node_held);         // (pre-step nnode)
  const Eigen::MatrixX3d old_held = std::move(cm.held_displacement);
  cm.tet_detached.assign(size_t(nt), 0);
  cm.node_held.assign(size_t(nn), 0);
  cm.held_displacement = Eigen::MatrixX3d::Zero(nn, 3);
  std::vector<DetachedPiece> fresh;
  for (DetachedPiece& piece : find_detached(cm.mesh, cm.node_clamped)) {
    bool is_new = false;
    for (int t : piece.tets) {
      cm.tet_detached[size_t(t)] = 1;
      is_new |= !was_detached[size_t(rec.tet_parent[size_t(t)])];
    }
    for (int v : piece.nodes) {
      if (cm.node_clamped[size_t(v)]) continue;
      cm.node_held[size_t(v)] = 1;
      const bool before = size_t(v) < was_held.size() && was_held[size_t(v)];
      cm.held_displacement.row(v) = before ? old_held.row(v) : u.row(v);
    }
    if (is_new) fresh.push_back(std::move(piece));
  }
  cm.node_fixed.resize(size_t(nn));
  for (int v = 0; v < nn; ++v) cm.node_fixed[size_t(v)] = cm.node_clamped[size_t(v)] || cm.node_held[size_t(v)];
  return fresh;
}

bool is_held(const CutMesh& cm, int n) {
  return n >= 0 && size_t(n) < cm.node_held.size() && cm.node_held[size_t(n)];
}

void hold_detached(const CutMesh& cm, Eigen::MatrixX3d& u) {
  if (cm.detached_pieces == 0) return;
  for (int v = 0; v < int(cm.node_held.size()) && v < u.rows(); ++v)
    if (cm.node_held[size_t(v)]) u.row(v) = cm.held_displacement.row(v);
}

DetachedCounts detached_counts(const CutMesh& cm) {
  DetachedCounts c;
  c.pieces = cm.detached_pieces;
  std::vector<char> node(size_t(cm.mesh.num_nodes()), 0);
  for (int t = 0; t < cm.mesh.num_tets(); ++t) {
    if (!cm.tet_detached[size_t(t)]) continue;
    ++c.tets;
    for (int k = 0; k < 4; ++k) node[size_t(cm.mesh.tets(t, k))] = 1;
  }
  for (char v : node) c.nodes += v;
  return c;
}

int count_components(const mesh::TetMesh& mesh) {
  std::vector<int> parent(size_t(mesh.num_nodes()));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[size_t(v)] != v) v = parent[size_t(v)] = parent[size_t(parent[size_t(v)])];
    return v;
  };
  std::vector<char> used(size_t(mesh.num_nodes()), 0);
  for (int t = 0; t < mesh.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) {
      used[size_t(mesh.tets(t, k))] = 1;
      if (k > 0) {
        const int a = find(mesh.tets(t, 0)), b = find(mesh.tets(t, k));
        if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
      }
    }
  int n = 0;
  for (int v = 0; v < mesh.num_nodes(); ++v) n += used[size_t(v)] && find(v) == v;
  return n;
}

}  // namespace softcut::cut
