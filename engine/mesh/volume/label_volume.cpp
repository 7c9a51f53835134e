#include "mesh/volume/label_volume.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <map>
#include <set>

#include "mesh/surface.hpp"

namespace softcut::mesh {

TetMesh mesh_label_volume(const LabelVolume& v, const VoxelMeshOptions& opt, Diagnostics& diag) {
  if (std::int64_t(v.labels.size()) != v.num_voxels())
    fail(v.source, ": label volume holds ", v.labels.size(), " values for ", v.num_voxels(), " voxels");
  std::map<int, std::int64_t> count;
  for (auto l : v.labels) ++count[l];
  std::set<int> want(opt.labels.begin(), opt.labels.end());
  if (want.empty())
    for (const auto& [l, n] : count)
      if (l != 0) want.insert(l);
  auto present = [&] {
    std::string s;
    for (const auto& [l, n] : count) s += cat(s.empty() ? "" : ", ", l, " (", n, " voxels)");
    return s;
  };
  for (int l : want)
    if (!count.count(l)) fail(v.source, ": label ", l, " does not occur; labels present: ", present());
  if (want.empty()) fail(v.source, ": no nonzero label to mesh; labels present: ", present());
  std::vector<char> sel(v.labels.size(), 0);
  std::int64_t nsel = 0;
  Eigen::Vector3i lo = v.size, hi = Eigen::Vector3i::Constant(-1);
  for (int k = 0; k < v.size(2); ++k)
    for (int j = 0; j < v.size(1); ++j)
      for (int i = 0; i < v.size(0); ++i) {
        const auto n = v.index(i, j, k);
        if (!want.count(v.labels[size_t(n)])) continue;
        sel[size_t(n)] = 1;
        ++nsel;
        lo = lo.cwiseMin(Eigen::Vector3i(i, j, k));
        hi = hi.cwiseMax(Eigen::Vector3i(i, j, k));
      }
  if (nsel * 6 > INT_MAX) fail(v.source, ": ", nsel, " selected voxels give too many tets; crop or downsample");
  if (double(nsel) * 6 > opt.max_tets)
    fail(v.source, ": ", nsel, " selected voxels give ", nsel * 6, " tetrahedra, over the limit of ", std::llround(opt.max_tets),
         "; crop or downsample the image, or mesh it with --mesher cgal (", opt.raise, ")");
  if (opt.smooth_iterations < 0 || opt.smooth_iterations > kMaxSmoothIterations)
    fail(v.source, ": smoothing passes must be in 0..", kMaxSmoothIterations, ", got ", opt.smooth_iterations);
  // Lattice over the selected voxels' bounding box (corners lo .. hi+1).
  const Eigen::Vector3i dim = (hi - lo).array() + 2;
  auto lat = [&](int i, int j, int k) {
    return std::int64_t(i - lo(0)) + std::int64_t(dim(0)) * ((j - lo(1)) + std::int64_t(dim(1)) * (k - lo(2)));
  };
  std::vector<int> node_of(size_t(dim.cast<std::int64_t>().prod()), -1);
  for (int k = lo(2); k <= hi(2); ++k)
    for (int j = lo(1); j <= hi(1); ++j)
      for (int i = lo(0); i <= hi(0); ++i)
        if (sel[size_t(v.index(i, j, k))])
          for (int c = 0; c < 8; ++c) node_of[size_t(lat(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2)))] = 0;
  int nn = 0;
  for (auto& id : node_of)
    if (id == 0) id = nn++;
  TetMesh m;
  m.nodes.resize(nn, 3);
  for (int k = lo(2); k <= hi(2) + 1; ++k)
    for (int j = lo(1); j <= hi(1) + 1; ++j)
      for (int i = lo(0); i <= hi(0) + 1; ++i)
        if (const int id = node_of[size_t(lat(i, j, k))]; id >= 0)
          m.nodes.row(id) = (v.origin + v.directions * (Eigen::Vector3d(i, j, k).array() - 0.5).matrix()).transpose();
  static constexpr int kPaths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  m.tets.resize(Eigen::Index(6 * nsel), 4);
  m.labels.resize(Eigen::Index(6 * nsel));
  int t = 0;
  for (int k = lo(2); k <= hi(2); ++k)
    for (int j = lo(1); j <= hi(1); ++j)
      for (int i = lo(0); i <= hi(0); ++i) {
        const auto n = v.index(i, j, k);
        if (!sel[size_t(n)]) continue;
        for (const auto& path : kPaths) {
          int c[3] = {i, j, k};
          m.tets(t, 0) = node_of[size_t(lat(c[0], c[1], c[2]))];
          for (int s = 0; s < 3; ++s) {
            ++c[path[s]];
            m.tets(t, s + 1) = node_of[size_t(lat(c[0], c[1], c[2]))];
          }
          if (signed_volume(m, t) < 0) std::swap(m.tets(t, 2), m.tets(t, 3));
          m.labels(t) = v.labels[size_t(n)];
          ++t;
        }
      }
  // Surface edges used by other than two faces: voxels meeting along an edge.
  const long bad = surface_edges(extract_surface(m)).odd;
  if (bad > 0)
    diag.warn(v.source, ": ", bad, " surface edge(s) are shared by more than two surface faces (voxels touching "
              "only along an edge); the mesh is conforming but its surface is not a manifold there");
  if (opt.smooth_iterations > 0) {
    const int rejected = smooth_surface(m, opt.smooth_iterations, opt.min_volume_fraction);
    if (rejected > 0)
      diag.warn(v.source, ": surface smoothing skipped ", rejected, " node moves that would have flattened a tet");
  }
  return m;
}

int smooth_surface(TetMesh& m, int iterations, double min_volume_fraction) {
  if (iterations < 0) fail("smoothing: iterations must be >= 0, got ", iterations);
  if (!(min_volume_fraction > 0 && min_volume_fraction < 1))
    fail("smoothing: minimum volume fraction must lie in (0, 1), got ", min_volume_fraction);
  const Surface s = extract_surface(m);
  const int nn = m.num_nodes();
  std::vector<std::vector<int>> nbr(static_cast<size_t>(nn)), tets_at(static_cast<size_t>(nn));
  for (Eigen::Index f = 0; f < s.faces.rows(); ++f)
    for (int e = 0; e < 3; ++e) {
      const int a = s.faces(f, e), b = s.faces(f, (e + 1) % 3);
      nbr[size_t(a)].push_back(b);
      nbr[size_t(b)].push_back(a);
    }
  for (auto& n : nbr) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  for (int t = 0; t < m.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) tets_at[size_t(m.tets(t, k))].push_back(t);
  Eigen::VectorXd floor_vol(m.num_tets());
  for (int t = 0; t < m.num_tets(); ++t) floor_vol(t) = min_volume_fraction * signed_volume(m, t);
  auto ok = [&](int v) {
    for (int t : tets_at[size_t(v)])
      if (!(signed_volume(m, t) >= floor_vol(t))) return false;
    return true;
  };
  int rejected = 0;
  for (int it = 0; it < iterations; ++it)
    for (double factor : {0.5, -0.53}) {
      Eigen::MatrixX3d target = m.nodes;
      for (int v : s.nodes) {
        Eigen::RowVector3d avg = Eigen::RowVector3d::Zero();
        for (int w : nbr[size_t(v)]) avg += m.nodes.row(w);
        avg /= double(nbr[size_t(v)].size());
        target.row(v) = m.nodes.row(v) + factor * (avg - m.nodes.row(v));
      }
      for (int v : s.nodes) {
        const Eigen::RowVector3d old = m.nodes.row(v);
        bool moved = false;
        for (double step : {1.0, 0.5, 0.25}) {
          m.nodes.row(v) = old + step * (target.row(v) - old);
          if (ok(v)) {
            moved = true;
            break;
          }
        }
        if (!moved) m.nodes.row(v) = old, ++rejected;
      }
    }
  return rejected;
}

}  // namespace softcut::mesh
