#include "mesh/generate/tube.hpp"

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "mesh/generate/extrude.hpp"

namespace softcut::mesh {

MeshSize tube_size(double r, double a, double l) { return {(r + 1) * a * (l + 1), 6 * r * a * l}; }

TubeOptions resolve_tube(const TubeOptions& opt, bool check_target) {
  TubeOptions o = opt;
  if (!(o.inner_radius > 0 && o.outer_radius > o.inner_radius && std::isfinite(o.outer_radius)))
    fail("tube: need 0 < inner radius < outer radius, got ", o.inner_radius, " and ", o.outer_radius, " m");
  if (!(o.length > 0 && std::isfinite(o.length))) fail("tube: length must be > 0 m, got ", o.length);
  if (o.radial < 0 || o.around < 0 || o.layers < 0 || o.target_tets < 0 || o.target_nodes < 0)
    fail("tube: resolution and targets must be >= 0");
  const bool any = o.radial > 0 || o.around > 0 || o.layers > 0;
  if (any && !(o.radial > 0 && o.around > 0 && o.layers > 0)) fail("tube: give radial, around and layers, or none");
  if (any && o.around < 3) fail("tube: need at least 3 cells around the axis, got ", o.around);
  const auto check_size = [](double r, double a, double l) { check_mesh_size("tube", tube_size(r, a, l)); };
  if (any) {
    check_size(o.radial, o.around, o.layers);
    return o;
  }
  const double wall = o.outer_radius - o.inner_radius, mid = 0.5 * (o.outer_radius + o.inner_radius);
  if (o.target_tets == 0 && o.target_nodes == 0) {
    o.radial = 2;
    const double h = wall / o.radial;
    const double around = std::max(6.0, std::round(2 * std::numbers::pi * mid / h));
    const double layers = std::max(1.0, std::round(o.length / h));
    check_size(o.radial, around, layers);
    o.around = int(around);
    o.layers = int(layers);
    return o;
  }
  double best = 1e300;
  for (int r = 1; r <= 32; ++r)
    for (int a = 6; a <= 256; ++a)
      for (int l = 1; l <= 256; ++l) {
        const long nodes = long(r + 1) * a * (l + 1), tets = 6L * r * a * l;
        const double s = resolution_score(
            nodes, tets, o.target_nodes, o.target_tets,
            Eigen::Vector3d(wall / r, 2 * std::numbers::pi * mid / a, o.length / l));
        if (s < best) best = s, o.radial = r, o.around = a, o.layers = l;
      }
  if (check_target) check_target_met("tube", tube_size(o.radial, o.around, o.layers), o.target_nodes, o.target_tets, "radial, around, layers");
  return o;
}

TetMesh generate_tube(const TubeOptions& opt) {
  const TubeOptions o = resolve_tube(opt);
  const int nr = o.radial, na = o.around;
  auto id = [&](int ir, int it) { return ir + (nr + 1) * (it % na); };
  Section s;
  s.num_points = (nr + 1) * na;
  s.boundary.assign(size_t(s.num_points), 0);
  for (int it = 0; it < na; ++it) s.boundary[size_t(id(0, it))] = s.boundary[size_t(id(nr, it))] = 1;
  s.triangles.resize(2 * nr * na, 3);
  int t = 0;
  for (int it = 0; it < na; ++it)
    for (int ir = 0; ir < nr; ++ir) {
      s.triangles.row(t++) << id(ir, it), id(ir + 1, it), id(ir + 1, it + 1);
      s.triangles.row(t++) << id(ir, it), id(ir + 1, it + 1), id(ir, it + 1);
    }
  const double dr = (o.outer_radius - o.inner_radius) / nr, da = 2 * std::numbers::pi / na, dz = o.length / o.layers;
  const auto place = [&](int p, int l, const Eigen::Vector3d& off) {
    const double r = o.inner_radius + (p % (nr + 1) + off.x()) * dr, a = (p / (nr + 1) + off.y()) * da;
    return Eigen::Vector3d(o.base_center + Eigen::Vector3d(r * std::cos(a), r * std::sin(a), (l + off.z()) * dz));
  };
  return extrude_section(s, o.layers, place, o.jitter, o.seed, o.label, "tube");
}

std::vector<int> tube_hole_nodes(const TetMesh& m, const TubeOptions& o) {
  const double tol = 1e-4 * (o.outer_radius - o.inner_radius);
  std::vector<int> ids;
  for (int i = 0; i < m.num_nodes(); ++i) {
    const Eigen::Vector3d d = m.node(i) - o.base_center;
    const double r = std::hypot(d.x(), d.y());
    if (std::abs(r - o.inner_radius) <= tol && d.z() >= -tol && d.z() <= o.length + tol) ids.push_back(i);
  }
  return ids;
}

}  // namespace softcut::mesh
