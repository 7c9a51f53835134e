#include "mesh/surface.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <map>

#include "core/error.hpp"

namespace softcut::mesh {

namespace {

struct FaceKey {
  std::array<int, 3> sorted;
  int tet, local;
};

// Every face of the tets with tet_mask[t] != 0 (all tets when the mask is
// empty), sorted by node triple, then tet: a face used by two tets comes out
// as two neighbours. O(F log F), no hashing, deterministic.
std::vector<FaceKey> sorted_faces(const TetMesh& m, const std::vector<char>& tet_mask) {
  std::vector<FaceKey> keys;
  keys.reserve(size_t(m.num_tets()) * 4);
  for (int t = 0; t < m.num_tets(); ++t) {
    if (!tet_mask.empty() && !tet_mask[size_t(t)]) continue;
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> v = {m.tets(t, kTetFaces[f][0]), m.tets(t, kTetFaces[f][1]),
                              m.tets(t, kTetFaces[f][2])};
      std::sort(v.begin(), v.end());
      keys.push_back({v, t, f});
    }
  }
  std::sort(keys.begin(), keys.end(), [](const FaceKey& a, const FaceKey& b) {
    return a.sorted != b.sorted ? a.sorted < b.sorted : a.tet < b.tet;
  });
  return keys;
}

// The surface of the given (tet, local face) pairs, in that order, each
// oriented as the face of its tet.
Surface surface_of(const TetMesh& m, const std::vector<std::pair<int, int>>& faces) {
  Surface s;
  s.faces.resize(Eigen::Index(faces.size()), 3);
  s.face_tet.resize(Eigen::Index(faces.size()));
  std::vector<char> on(size_t(m.num_nodes()), 0);
  for (size_t i = 0; i < faces.size(); ++i) {
    const auto [t, f] = faces[i];
    for (int k = 0; k < 3; ++k) {
      const int v = m.tets(t, kTetFaces[f][k]);
      s.faces(Eigen::Index(i), k) = v;
      on[size_t(v)] = 1;
    }
    s.face_tet(Eigen::Index(i)) = t;
  }
  for (int v = 0; v < m.num_nodes(); ++v)
    if (on[size_t(v)]) s.nodes.push_back(v);
  return s;
}

}  // namespace

Surface extract_surface(const TetMesh& m, const std::vector<char>& tet_mask) {
  // A face that appears once is on the boundary.
  const std::vector<FaceKey> keys = sorted_faces(m, tet_mask);
  std::vector<std::pair<int, int>> boundary;  // (tet, local face)
  for (size_t i = 0; i < keys.size();) {
    size_t j = i + 1;
    while (j < keys.size() && keys[j].sorted == keys[i].sorted) ++j;
    if (j - i == 1) boundary.emplace_back(keys[i].tet, keys[i].local);
    i = j;
  }
  std::sort(boundary.begin(), boundary.end());
  return surface_of(m, boundary);
}

Surface group_boundaries(const TetMesh& m, const std::vector<int>& tet_group) {
  if (tet_group.empty()) return surface_of(m, {});
  if (int(tet_group.size()) != m.num_tets())
    fail("group_boundaries: ", tet_group.size(), " group ids for ", m.num_tets(), " tets");
  std::map<int, int> count;  // group -> tets (groups are any ids, so not a vector)
  for (int g : tet_group) ++count[g];
  const int common = std::max_element(count.begin(), count.end(), [](const auto& a, const auto& b) {
                       return a.second < b.second;
                     })->first;
  const std::vector<FaceKey> keys = sorted_faces(m, {});
  std::vector<std::pair<int, int>> inner;  // (tet, local face) of the inclusion's side
  for (size_t i = 0; i + 1 < keys.size(); ++i) {
    const FaceKey& a = keys[i];
    const FaceKey& b = keys[i + 1];
    if (a.sorted != b.sorted) continue;
    const int ga = tet_group[size_t(a.tet)], gb = tet_group[size_t(b.tet)];
    if (ga != gb) {
      const bool a_inside = gb == common || (ga != common && ga > gb);
      const FaceKey& in = a_inside ? a : b;
      inner.emplace_back(in.tet, in.local);
    }
    ++i;
  }
  return surface_of(m, inner);
}

std::vector<char> surface_node_mask(const TetMesh& m, const Surface& s) {
  std::vector<char> mask(size_t(m.num_nodes()), 0);
  for (int v : s.nodes) mask[size_t(v)] = 1;
  return mask;
}

Eigen::MatrixX3d vertex_normals(const TetMesh& m, const Surface& s, const Eigen::MatrixX3d& positions) {
  const Eigen::MatrixX3d& x = positions.rows() ? positions : m.nodes;
  Eigen::MatrixX3d n = Eigen::MatrixX3d::Zero(m.num_nodes(), 3);
  for (Eigen::Index f = 0; f < s.faces.rows(); ++f) {
    const Eigen::Vector3d a = x.row(s.faces(f, 0)), b = x.row(s.faces(f, 1)), c = x.row(s.faces(f, 2));
    const Eigen::RowVector3d area_normal = 0.5 * (b - a).cross(c - a).transpose();
    for (int k = 0; k < 3; ++k) n.row(s.faces(f, k)) += area_normal;
  }
  for (Eigen::Index i = 0; i < n.rows(); ++i) {
    const double len = n.row(i).norm();
    if (len > 0) n.row(i) /= len;
  }
  return n;
}

SurfaceEdges surface_edges(const Surface& s) {
  std::map<std::pair<int, int>, int> faces_of;
  for (Eigen::Index f = 0; f < s.faces.rows(); ++f)
    for (int e = 0; e < 3; ++e) {
      const int a = s.faces(f, e), b = s.faces(f, (e + 1) % 3);
      ++faces_of[{std::min(a, b), std::max(a, b)}];
    }
  SurfaceEdges out;
  out.edges = int(faces_of.size());
  for (const auto& [e, n] : faces_of) out.odd += n != 2;
  out.euler = int(s.nodes.size()) - out.edges + int(s.faces.rows());
  return out;
}

}  // namespace softcut::mesh
