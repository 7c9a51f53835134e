#include "mesh/generate/extrude.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <random>

#include "core/error.hpp"

namespace softcut::mesh {

TetMesh extrude_section(const Section& s, int layers, const PlacePoint& place, double jitter, unsigned seed,
                        int label, const char* what) {
  if (layers < 1) fail(what, ": need at least one layer, got ", layers);
  if (!(jitter >= 0 && jitter < 0.25)) fail(what, ": jitter must lie in [0, 0.25), got ", jitter);
  const int np = s.num_points, ntri = int(s.triangles.rows());
  TetMesh m;
  m.nodes.resize(Eigen::Index(np) * (layers + 1), 3);
  for (int l = 0; l <= layers; ++l)
    for (int p = 0; p < np; ++p) m.nodes.row(p + np * l) = place(p, l, Eigen::Vector3d::Zero()).transpose();
  m.tets.resize(Eigen::Index(3) * ntri * layers, 4);
  int t = 0;
  for (int l = 0; l < layers; ++l)
    for (int f = 0; f < ntri; ++f) {
      int v[3] = {s.triangles(f, 0), s.triangles(f, 1), s.triangles(f, 2)};
      std::sort(v, v + 3);
      const int b0 = v[0] + np * l, b1 = v[1] + np * l, b2 = v[2] + np * l;
      const int t0 = b0 + np, t1 = b1 + np, t2 = b2 + np;
      const int split[3][4] = {{b0, b1, b2, t2}, {b0, b1, t1, t2}, {b0, t0, t1, t2}};
      for (const auto& tet : split) {
        for (int k = 0; k < 4; ++k) m.tets(t, k) = tet[k];
        if (signed_volume(m, t) < 0) std::swap(m.tets(t, 2), m.tets(t, 3));
        ++t;
      }
    }
  if (jitter > 0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int l = 1; l < layers; ++l)
      for (int p = 0; p < np; ++p) {
        if (s.boundary[size_t(p)]) continue;
        const Eigen::Vector3d off(jitter * u(rng), jitter * u(rng), jitter * u(rng));
        m.nodes.row(p + np * l) = place(p, l, off).transpose();
      }
    for (int k = 0; k < m.num_tets(); ++k)
      if (!(signed_volume(m, k) > 0))
        fail(what, ": jitter ", jitter, " (seed ", seed, ") inverts tetrahedron ", k, "; use a smaller jitter");
  }
  m.labels = Eigen::VectorXi::Constant(m.num_tets(), label);
  return m;
}

double resolution_score(long nodes, long tets, int target_nodes, int target_tets, const Eigen::Vector3d& cell) {
  double miss = 0;
  if (target_nodes > 0) miss = std::max(miss, std::abs(double(nodes) / target_nodes - 1));
  if (target_tets > 0) miss = std::max(miss, std::abs(double(tets) / target_tets - 1));
  return miss + 0.05 * std::log(cell.maxCoeff() / cell.minCoeff());
}

void check_mesh_size(const char* what, const MeshSize& size) {
  if (!(size.nodes <= INT_MAX && size.tets <= INT_MAX))
    fail(what, ": the requested resolution gives too many nodes or tetrahedra (", size.nodes, " nodes, ", size.tets,
         " tets; at most ", INT_MAX, " each); use fewer cells");
}

void check_target_met(const char* what, long nodes, long tets, int target_nodes, int target_tets, const char* cells) {
  const auto missed = [](double got, int want) { return want > 0 && std::abs(got / want - 1) > kTargetTolerance; };
  if (missed(double(nodes), target_nodes) || missed(double(tets), target_tets))
    fail(what, ": cannot meet ", target_tets > 0 ? cat("target_tets ", target_tets) : std::string(),
         target_tets > 0 && target_nodes > 0 ? " and " : "", target_nodes > 0 ? cat("target_nodes ", target_nodes) : std::string(),
         " within ", int(kTargetTolerance * 100), " %: the closest resolution its search reaches gives ", nodes, " nodes and ",
         tets, " tets; ask for a target in reach, or give the cell counts (", cells, ")");
}

}  // namespace softcut::mesh
