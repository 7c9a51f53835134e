#include "mesh/mesher/shape.hpp"

#include <algorithm>

namespace softcut::mesh {

std::vector<double> label_volumes(const LabeledShape& s, int n) {
  std::vector<double> vol(size_t(s.labels.empty() ? 1 : s.labels.back() + 1), 0.0);
  const Eigen::Vector3d lo = s.bounds.min(), step = s.bounds.sizes() / n;
  const double cell = step.prod();
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int l = s.label(lo + step.cwiseProduct(Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5)));
        if (l >= int(vol.size())) vol.resize(size_t(l) + 1, 0.0);
        if (l >= 0) vol[size_t(l)] += cell;
      }
  return vol;
}

}  // namespace softcut::mesh
