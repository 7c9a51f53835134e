#include "mesh/generate/band.hpp"

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "mesh/generate/extrude.hpp"

namespace softcut::mesh {

MeshSize band_size(double a, double w, double t) { return {(a + 1) * (w + 1) * (t + 1), 6 * a * w * t}; }

BandOptions resolve_band(const BandOptions& opt, bool check_target) {
  BandOptions o = opt;
  for (double v : {o.length, o.width, o.thickness})
    if (!(v > 0 && std::isfinite(v)))
      fail("band: length, width and thickness must be > 0 m, got ", o.length, " ", o.width, " ", o.thickness);
  if (!(o.flare >= 1 && o.flare <= 10)) fail("band: flare must lie in [1, 10], got ", o.flare);
  if (!(std::abs(o.twist_deg) <= 720)) fail("band: twist must lie in [-720, 720] degrees, got ", o.twist_deg);
  if (o.along < 0 || o.across < 0 || o.through < 0 || o.target_tets < 0 || o.target_nodes < 0)
    fail("band: resolution and targets must be >= 0");
  const bool any = o.along > 0 || o.across > 0 || o.through > 0;
  if (any && !(o.along > 0 && o.across > 0 && o.through > 0)) fail("band: give along, across and through, or none");
  const auto check_size = [](double a, double w, double t) { check_mesh_size("band", band_size(a, w, t)); };
  if (any) {
    check_size(o.along, o.across, o.through);
    return o;
  }
  if (o.target_tets == 0 && o.target_nodes == 0) {
    o.through = 2;
    const double h = o.thickness / o.through;
    const double across = std::max(1.0, std::round(o.width / h));
    const double along = std::max(1.0, std::round(o.length / h));
    check_size(along, across, o.through);
    o.across = int(across);
    o.along = int(along);
    return o;
  }
  double best = 1e300;
  for (int t = 1; t <= 16; ++t)
    for (int w = 1; w <= 64; ++w)
      for (int a = 1; a <= 400; ++a) {
        const long nodes = long(a + 1) * (w + 1) * (t + 1), tets = 6L * a * w * t;
        const double s = resolution_score(nodes, tets, o.target_nodes, o.target_tets,
                                          Eigen::Vector3d(o.length / a, o.width / w, o.thickness / t));
        if (s < best) best = s, o.along = a, o.across = w, o.through = t;
      }
  if (check_target) check_target_met("band", band_size(o.along, o.across, o.through), o.target_nodes, o.target_tets, "along, across, through");
  return o;
}

TetMesh generate_band(const BandOptions& opt) {
  const BandOptions o = resolve_band(opt);
  const int nw = o.across, nt = o.through;
  auto id = [&](int iw, int it) { return iw + (nw + 1) * it; };
  Section s;
  s.num_points = (nw + 1) * (nt + 1);
  s.boundary.assign(size_t(s.num_points), 0);
  for (int it = 0; it <= nt; ++it)
    for (int iw = 0; iw <= nw; ++iw) s.boundary[size_t(id(iw, it))] = iw == 0 || iw == nw || it == 0 || it == nt;
  s.triangles.resize(2 * nw * nt, 3);
  int t = 0;
  for (int it = 0; it < nt; ++it)
    for (int iw = 0; iw < nw; ++iw) {
      s.triangles.row(t++) << id(iw, it), id(iw + 1, it), id(iw + 1, it + 1);
      s.triangles.row(t++) << id(iw, it), id(iw + 1, it + 1), id(iw, it + 1);
    }
  const double twist = o.twist_deg * std::numbers::pi / 180;
  const auto place = [&](int p, int l, const Eigen::Vector3d& off) {
    const double xi = 2 * (l + off.z()) / o.along - 1;  // -1 .. 1 along the length
    const double u = 2 * (p % (nw + 1) + off.x()) / nw - 1, v = 2 * (p / (nw + 1) + off.y()) / nt - 1;
    const double blend = xi * xi * xi * xi;
    const double hw = 0.5 * o.width * (1 + (o.flare - 1) * blend);
    const double ht = 0.5 * o.thickness * (1 + (std::sqrt(o.flare) - 1) * blend);
    const double phi = 0.5 * twist * xi, c = std::cos(phi), sn = std::sin(phi);
    return Eigen::Vector3d(o.base_center + Eigen::Vector3d(c * u * hw - sn * v * ht, sn * u * hw + c * v * ht,
                                                           0.5 * (xi + 1) * o.length));
  };
  return extrude_section(s, o.along, place, o.jitter, o.seed, o.label, "band");
}

}  // namespace softcut::mesh
