#include "mesh/generate/cylinder.hpp"

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "mesh/generate/extrude.hpp"

namespace softcut::mesh {

MeshSize cylinder_size(double k, double l) { return {(1 + 3 * k * (k + 1)) * (l + 1), 18 * k * k * l}; }

CylinderOptions resolve_cylinder(const CylinderOptions& opt, bool check_target) {
  CylinderOptions o = opt;
  if (!(o.radius > 0 && std::isfinite(o.radius))) fail("cylinder: radius must be > 0 m, got ", o.radius);
  if (!(o.length > 0 && std::isfinite(o.length))) fail("cylinder: length must be > 0 m, got ", o.length);
  if (o.rings < 0 || o.layers < 0 || o.target_tets < 0 || o.target_nodes < 0)
    fail("cylinder: resolution and targets must be >= 0");
  if ((o.rings > 0) != (o.layers > 0)) fail("cylinder: give both rings and layers, or neither");
  const auto check_size = [](double k, double l) { check_mesh_size("cylinder", cylinder_size(k, l)); };
  if (o.rings > 0) {
    check_size(o.rings, o.layers);
    return o;
  }
  if (o.target_tets == 0 && o.target_nodes == 0) {
    o.rings = 4;
    const double layers = std::max(1.0, std::round(o.length / (o.radius / o.rings)));
    check_size(o.rings, layers);
    o.layers = int(layers);
    return o;
  }
  double best = 1e300;
  for (int k = 1; k <= 64; ++k)
    for (int l = 1; l <= 400; ++l) {
      const long nodes = (1 + 3L * k * (k + 1)) * (l + 1), tets = 18L * k * k * l;
      const double h = o.radius / k;
      const double s = resolution_score(nodes, tets, o.target_nodes, o.target_tets,
                                        Eigen::Vector3d(h, h, o.length / l));
      if (s < best) best = s, o.rings = k, o.layers = l;
    }
  if (check_target) check_target_met("cylinder", cylinder_size(o.rings, o.layers), o.target_nodes, o.target_tets, "rings, layers");
  return o;
}

TetMesh generate_cylinder(const CylinderOptions& opt) {
  const CylinderOptions o = resolve_cylinder(opt);
  const int K = o.rings;
  auto ring_start = [](int k) { return k == 0 ? 0 : 1 + 3 * k * (k - 1); };
  Section s;
  s.num_points = 1 + 3 * K * (K + 1);
  s.boundary.assign(size_t(s.num_points), 0);
  Eigen::MatrixX2d xy(s.num_points, 2);
  xy.row(0).setZero();
  const double h = o.radius / K, hz = o.length / o.layers;
  for (int k = 1; k <= K; ++k)
    for (int j = 0; j < 6 * k; ++j) {
      const double a = 2 * std::numbers::pi * j / (6 * k);
      xy.row(ring_start(k) + j) << k * h * std::cos(a), k * h * std::sin(a);
      if (k == K) s.boundary[size_t(ring_start(k) + j)] = 1;
    }
  s.triangles.resize(6 * K * K, 3);
  int t = 0;
  for (int k = 1; k <= K; ++k) {
    auto outer = [&](int sec, int i) { return ring_start(k) + (sec * k + i) % (6 * k); };
    auto inner = [&](int sec, int i) { return k == 1 ? 0 : ring_start(k - 1) + (sec * (k - 1) + i) % (6 * (k - 1)); };
    for (int sec = 0; sec < 6; ++sec) {
      for (int i = 0; i < k; ++i) s.triangles.row(t++) << outer(sec, i), outer(sec, i + 1), inner(sec, i);
      for (int i = 0; i + 1 < k; ++i) s.triangles.row(t++) << inner(sec, i), outer(sec, i + 1), inner(sec, i + 1);
    }
  }
  const auto place = [&](int p, int l, const Eigen::Vector3d& off) {
    return Eigen::Vector3d(o.base_center + Eigen::Vector3d(xy(p, 0) + off.x() * h, xy(p, 1) + off.y() * h,
                                                           (l + off.z()) * hz));
  };
  return extrude_section(s, o.layers, place, o.jitter, o.seed, o.label, "cylinder");
}

}  // namespace softcut::mesh
