#pragma once
// Internal to the cutter: tet-mesh adjacency helpers shared by the splitting
// (cutter.cpp) and separation (separate.cpp) steps.
#include <algorithm>
#include <array>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace softcut::cut::detail {

using Tet = std::array<int, 4>;
using FaceKey = std::array<int, 3>;  // sorted node ids

// Node -> cuttable tets containing it (CSR, each list ascending).
struct Adjacency {
  std::vector<int> start;  // (nnode + 1)
  std::vector<int> tets;   // (4 * nregion)

  void build(const mesh::TetMesh& m, const std::vector<char>& cuttable) {
    const int nn = m.num_nodes(), nt = m.num_tets();
    start.assign(size_t(nn) + 1, 0);
    for (int t = 0; t < nt; ++t)
      if (cuttable[size_t(t)])
        for (int k = 0; k < 4; ++k) ++start[size_t(m.tets(t, k)) + 1];
    for (int v = 0; v < nn; ++v) start[size_t(v) + 1] += start[size_t(v)];
    tets.resize(size_t(start.back()));
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int t = 0; t < nt; ++t)
      if (cuttable[size_t(t)])
        for (int k = 0; k < 4; ++k) tets[size_t(fill[size_t(m.tets(t, k))]++)] = t;
  }
  const int* begin(int v) const { return tets.data() + start[size_t(v)]; }
  const int* end(int v) const { return tets.data() + start[size_t(v) + 1]; }
};

inline Tet tet_of(const mesh::TetMesh& m, int t) { return {m.tets(t, 0), m.tets(t, 1), m.tets(t, 2), m.tets(t, 3)}; }

inline bool contains(const Tet& t, int v) { return t[0] == v || t[1] == v || t[2] == v || t[3] == v; }

inline FaceKey face_key(const Tet& t, int local_face) {
  FaceKey k = {t[size_t(mesh::kTetFaces[local_face][0])], t[size_t(mesh::kTetFaces[local_face][1])],
               t[size_t(mesh::kTetFaces[local_face][2])]};
  std::sort(k.begin(), k.end());
  return k;
}

// Shared nodes of two tets, sorted; the count is returned.
inline int shared_nodes(const Tet& a, const Tet& b, FaceKey& out) {
  int n = 0;
  for (int v : a)
    if (contains(b, v)) {
      if (n == 3) return 4;
      out[size_t(n++)] = v;
    }
  if (n == 3) std::sort(out.begin(), out.end());
  return n;
}

// The other cuttable tet sharing face `key` with tet t, or -1.
inline int neighbour(const mesh::TetMesh& m, const Adjacency& adj, int t, const FaceKey& key) {
  for (const int* u = adj.begin(key[0]); u != adj.end(key[0]); ++u)
    if (*u != t && contains(tet_of(m, *u), key[1]) && contains(tet_of(m, *u), key[2])) return *u;
  return -1;
}

// A face on the cut surface and the two tets sharing it (t1 < t2).
struct CutFace {
  FaceKey key;
  int t1, t2;
};

}  // namespace softcut::cut::detail
