#include "mesh/mesher/volume_shape.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <set>

#include "core/error.hpp"

namespace softcut::mesh {

LabeledShape volume_shape(const LabelVolume& v, const std::vector<int>& keep) {
  std::set<int> present;
  for (const auto l : v.labels)
    if (l != 0) present.insert(l);
  std::set<int> kept(keep.begin(), keep.end());
  if (kept.empty()) kept = present;
  for (int l : kept)
    if (l <= 0 || !present.count(l)) fail(v.source, ": label ", l, " does not occur in the image (it has ", present.size(), " nonzero labels)");
  if (kept.empty()) fail(v.source, ": the image has no nonzero label to mesh");
  const Eigen::Matrix3d dir = v.directions;
  if (!(std::abs(dir.determinant()) > 0)) fail(v.source, ": the voxel directions are degenerate");
  const Eigen::Matrix3d inv = dir.inverse();

  // Shared, so copies of the shape (CGAL copies its function) stay cheap.
  auto vol = std::make_shared<const LabelVolume>(v);
  auto keep_set = std::make_shared<const std::set<int>>(kept);
  LabeledShape s;
  s.name = "volume " + v.source;
  s.labels.assign(kept.begin(), kept.end());
  s.label = [vol, keep_set, inv](const Eigen::Vector3d& p) {
    const Eigen::Vector3d x = inv * (p - vol->origin);  // voxel-centre coordinates
    const Eigen::Vector3i i0 = x.array().floor().cast<int>();
    const Eigen::Vector3d f = x - i0.cast<double>();
    std::array<std::pair<int, double>, 8> w{};  // (label, weight), few distinct labels
    int n = 0;
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3i q = i0 + Eigen::Vector3i(c & 1, (c >> 1) & 1, (c >> 2) & 1);
      double weight = 1;
      for (int a = 0; a < 3; ++a) weight *= (c >> a) & 1 ? f(a) : 1 - f(a);
      int label = 0;
      if ((q.array() >= 0).all() && (q.array() < vol->size.array()).all()) {
        label = vol->labels[size_t(vol->index(q(0), q(1), q(2)))];
        if (!keep_set->count(label)) label = 0;
      }
      int k = 0;
      while (k < n && w[size_t(k)].first != label) ++k;
      if (k == n) w[size_t(n++)] = {label, 0.0};
      w[size_t(k)].second += weight;
    }
    int best = 0;
    for (int k = 1; k < n; ++k)
      if (w[size_t(k)].second > w[size_t(best)].second ||
          (w[size_t(k)].second == w[size_t(best)].second && w[size_t(k)].first < w[size_t(best)].first))
        best = k;
    return w[size_t(best)].first;
  };
  // The image's box grown by one voxel: interpolation ends on background there.
  Eigen::AlignedBox3d box;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d corner((c & 1) ? v.size(0) : -1, (c & 2) ? v.size(1) : -1, (c & 4) ? v.size(2) : -1);
    box.extend(v.origin + dir * corner);
  }
  s.bounds = box;
  return s;
}

}  // namespace softcut::mesh
