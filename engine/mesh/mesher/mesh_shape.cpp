// The one translation unit that includes CGAL (it takes ~30 s and ~3 GB to
// compile): everything else sees TetMesh and LabeledShape only.
#include "mesh/mesher/mesh_shape.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Random.h>
#include <CGAL/exude_mesh_3.h>
#include <CGAL/perturb_mesh_3.h>
#include <CGAL/refine_mesh_3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <array>
#include <map>
#include <unordered_map>

#include "mesh/quality.hpp"

namespace softcut::mesh {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Domain = CGAL::Labeled_mesh_domain_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;
using Point = K::Point_3;

Eigen::Vector3d vec(const Point& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}; }

// h(p) (or a fraction of it) as a Mesh_3 sizing field.
struct SizeField {
  using FT = K::FT;
  const MesherOptions* o;
  double scale;
  FT operator()(const Point& p, int, const Domain::Index&) const { return scale * local_size(*o, vec(p)); }
};

void check(const LabeledShape& s, const MesherOptions& o) {
  const auto positive = [&](double v, const char* name) {
    if (!(v > 0) || !std::isfinite(v)) fail(s.name, ": ", name, " must be a positive number of metres, got ", v);
  };
  positive(o.cell_size, "cell_size");
  if (o.fine_radius != 0) {
    positive(o.fine_radius, "fine_radius");
    positive(o.fine_size, "fine_size");
    if (o.fine_size > o.cell_size) fail(s.name, ": fine_size ", o.fine_size, " is larger than cell_size ", o.cell_size);
    if (!o.fine_center.allFinite()) fail(s.name, ": fine_center must be finite");
  }
  if (!(o.facet_distance > 0 && o.facet_distance <= 1)) fail(s.name, ": facet_distance must be in (0, 1], got ", o.facet_distance);
  if (!(o.facet_angle_deg > 0 && o.facet_angle_deg <= 30)) fail(s.name, ": facet_angle must be in (0, 30] degrees, got ", o.facet_angle_deg);
  if (!(o.radius_edge >= 2 && o.radius_edge < 1e3)) fail(s.name, ": radius_edge must be >= 2, got ", o.radius_edge);
  if (!(o.sliver_bound_deg >= 0 && o.sliver_bound_deg < 30)) fail(s.name, ": sliver_bound must be in [0, 30) degrees, got ", o.sliver_bound_deg);
  if (!(o.optimise_seconds > 0 && o.optimise_seconds <= 3600)) fail(s.name, ": optimise_seconds must be in (0, 3600], got ", o.optimise_seconds);
  if (s.bounds.isEmpty() || !s.bounds.min().allFinite() || !s.bounds.max().allFinite() || (s.bounds.sizes().array() <= 0).any())
    fail(s.name, ": the shape's bounding box is empty");
  // CGAL seeds the mesh with points where random segments cross the surface
  // and searches forever when there is none: an empty shape must be refused here.
  const auto vol = label_volumes(s);
  double inside = 0;
  for (size_t l = 1; l < vol.size(); ++l) inside += vol[l];
  if (!(inside > 0))
    fail(s.name, ": the mesher made no tetrahedra: no point of the shape's box is labelled on a 48^3 grid "
         "(the shape is empty or thinner than 1/48 of its box)");
}

// Puts points on every surface before refinement. make_mesh_3 seeds by
// shooting random segments from the box centre and misses surfaces behind
// others (a ball inside a ball came out as the inner ball alone), so the
// seeds come from a grid: where an edge between two samples crosses from
// one label to another, the surface point on it, kept when no seed lies
// within h of it (closer seeds make the refinement split around them).
void seed_surfaces(C3t3& c3t3, const Domain& domain, const LabeledShape& s, const MesherOptions& o) {
  const double h_min = o.fine_radius > 0 ? o.fine_size : o.cell_size;
  const int n = int(std::clamp(std::ceil(2 * s.bounds.sizes().maxCoeff() / h_min), 48.0, 160.0));
  const Eigen::Vector3d lo = s.bounds.min(), step = s.bounds.sizes() / n;
  const auto at = [&](int i, int j, int k) { return Eigen::Vector3d(lo + step.cwiseProduct(Eigen::Vector3d(i, j, k))); };
  const auto idx = [&](int i, int j, int k) { return size_t(i) + size_t(n + 1) * (size_t(j) + size_t(n + 1) * size_t(k)); };
  std::vector<int> label(size_t(n + 1) * (n + 1) * (n + 1));
  for (int k = 0; k <= n; ++k) {
    check_stopped(s.name, o, false);  // up to 160^3 samples: the deadline is polled per slice
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) label[idx(i, j, k)] = s.label(at(i, j, k));
  }
  // Kept seeds hashed by cells of the largest h: a seed's neighbours within
  // h lie in the 27 cells around it.
  const double bucket = o.cell_size;
  std::map<std::array<long, 3>, std::vector<Eigen::Vector3d>> kept;
  const auto key = [&](const Eigen::Vector3d& p) {
    return std::array<long, 3>{long(std::floor(p.x() / bucket)), long(std::floor(p.y() / bucket)), long(std::floor(p.z() / bucket))};
  };
  const auto crowded = [&](const Eigen::Vector3d& p) {
    const double h = local_size(o, p);
    const auto c = key(p);
    for (long dz = -1; dz <= 1; ++dz)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dx = -1; dx <= 1; ++dx)
          if (auto it = kept.find({c[0] + dx, c[1] + dy, c[2] + dz}); it != kept.end())
            for (const auto& q : it->second)
              if ((q - p).norm() < h) return true;
    return false;
  };
  auto intersect = domain.construct_intersection_object();
  auto& tr = c3t3.triangulation();
  for (int k = 0; k <= n; ++k) {
    check_stopped(s.name, o, false);
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        for (int axis = 0; axis < 3; ++axis) {
          Eigen::Vector3i q(i, j, k);
          if (++q(axis) > n || label[idx(i, j, k)] == label[idx(q(0), q(1), q(2))]) continue;
          const Eigen::Vector3d pa = at(i, j, k), pb = at(q(0), q(1), q(2));
          if (crowded(pa)) continue;
          const auto hit = intersect(K::Segment_3(Point(pa.x(), pa.y(), pa.z()), Point(pb.x(), pb.y(), pb.z())));
          if (std::get<2>(hit) == 0) continue;
          const Eigen::Vector3d x = vec(std::get<0>(hit));
          if (crowded(x)) continue;
          const auto v = tr.insert(Tr::Weighted_point(std::get<0>(hit)));
          if (v == Tr::Vertex_handle()) continue;
          c3t3.set_dimension(v, 2);
          c3t3.set_index(v, std::get<1>(hit));
          kept[key(x)].push_back(x);
        }
  }
}

}  // namespace

void check_stopped(const std::string& name, const MesherOptions& o, bool vertices_reached) {
  if (o.stop && o.stop->load()) throw TimeoutError(cat(name, ": meshing stopped at the time limit (--timeout)"));
  if (vertices_reached)
    fail(name, ": meshing stopped at ", o.max_vertices, " vertices, past what the tetrahedron limit allows; "
         "ask for fewer tetrahedra (a larger cell size) or raise the limit (--max-tets)");
}

std::size_t max_vertices_for(double max_tets) {
  if (!(max_tets < 1e15)) return 0;
  return std::size_t(std::max(1e4, max_tets / 3 + 1e4));
}

double local_size(const MesherOptions& o, const Eigen::Vector3d& p) {
  if (o.fine_radius <= 0) return o.cell_size;
  const double d = (p - o.fine_center).norm();
  const double t = std::clamp((d - o.fine_radius) / o.fine_radius, 0.0, 1.0);
  return o.fine_size + t * (o.cell_size - o.fine_size);
}

double estimate_tets(const LabeledShape& s, const MesherOptions& o) {
  check(s, o);
  // Delaunay refinement to a circumradius bound h leaves about 1 tet per
  // 0.21 h^3 of volume, measured on a ball and the liver at 1k..36k tets.
  constexpr double kVolumePerTet = 0.21;
  const int n = 48;
  const Eigen::Vector3d lo = s.bounds.min(), step = s.bounds.sizes() / n;
  const double cell = step.prod();
  double tets = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Eigen::Vector3d p = lo + step.cwiseProduct(Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5));
        if (s.label(p) > 0) tets += cell / (kVolumePerTet * std::pow(local_size(o, p), 3));
      }
  return tets;
}

TetMesh mesh_shape(const LabeledShape& s, const MesherOptions& o, MesherReport* report) {
  check(s, o);
  const auto t0 = std::chrono::steady_clock::now();
  CGAL::Random rng(o.seed);
  const Eigen::Vector3d lo = s.bounds.min(), hi = s.bounds.max();
  std::function<int(const Point&)> label = [&](const Point& p) { return s.label(vec(p)); };
  // Surface points are located by bisection to 1e-6 of the box diagonal.
  Domain domain(label, K::Iso_cuboid_3(Point(lo.x(), lo.y(), lo.z()), Point(hi.x(), hi.y(), hi.z())), 1e-6,
                CGAL::Null_subdomain_index(), &rng);
  namespace p = CGAL::parameters;
  const Criteria criteria(p::facet_angle = o.facet_angle_deg, p::facet_size = SizeField{&o, 1.0},
                          p::facet_distance = SizeField{&o, o.facet_distance},
                          p::cell_radius_edge_ratio = o.radius_edge, p::cell_size = SizeField{&o, 1.0});
  C3t3 c3t3;
  seed_surfaces(c3t3, domain, s, o);
  if (c3t3.triangulation().dimension() < 3)
    fail(s.name, ": too few surface points to start from: the shape is thinner than its sampling grid "
         "(1/48 of its box) or than cell_size");
  CGAL::Mesh_error_code error = CGAL::CGAL_MESH_3_NO_ERROR;
  // Refinement stops at the bounds; the optimisation passes (what
  // refine_mesh_3 would run next, called here so that a stopped refinement
  // is not optimised for another minute) only when it finished.
  CGAL::refine_mesh_3(c3t3, domain, criteria, p::no_lloyd(), p::no_odt(), p::no_perturb(), p::no_exude(),
                      p::mesh_3_options(p::maximal_number_of_vertices = o.max_vertices,
                                        p::pointer_to_error_code = &error,
                                        p::pointer_to_stop_atomic_boolean = const_cast<std::atomic<bool>*>(o.stop)));
  check_stopped(s.name, o, error == CGAL::CGAL_MESH_3_MAXIMAL_NUMBER_OF_VERTICES_REACHED);
  CGAL::perturb_mesh_3(c3t3, domain, p::time_limit = o.optimise_seconds, p::sliver_bound = o.sliver_bound_deg);
  CGAL::exude_mesh_3(c3t3, p::time_limit = o.optimise_seconds, p::sliver_bound = o.sliver_bound_deg);

  TetMesh m;
  const auto& tr = c3t3.triangulation();
  std::unordered_map<Tr::Vertex_handle, int> id;
  std::vector<Eigen::Vector3d> nodes;
  std::vector<Eigen::Vector4i> tets;
  std::vector<int> labels;
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    Eigen::Vector4i t;
    for (int v = 0; v < 4; ++v) {
      const auto h = c->vertex(v);
      auto [it, added] = id.emplace(h, int(nodes.size()));
      if (added) nodes.push_back(vec(tr.point(h).point()));
      t(v) = it->second;
    }
    tets.push_back(t);
    labels.push_back(int(c3t3.subdomain_index(c)));
  }
  if (tets.empty()) fail(s.name, ": the mesher made no tetrahedra (is the shape smaller than cell_size?)");
  m.nodes.resize(Eigen::Index(nodes.size()), 3);
  for (size_t i = 0; i < nodes.size(); ++i) m.nodes.row(Eigen::Index(i)) = nodes[i].transpose();
  m.tets.resize(Eigen::Index(tets.size()), 4);
  m.labels.resize(Eigen::Index(tets.size()));
  for (size_t t = 0; t < tets.size(); ++t) m.tets.row(Eigen::Index(t)) = tets[t].transpose(), m.labels(Eigen::Index(t)) = labels[t];
  Diagnostics diag;
  validate(m, s.name, diag);
  if (report) {
    report->nodes = m.num_nodes();
    report->tets = m.num_tets();
    report->min_dihedral_deg = tet_quality(m).min_dihedral_deg;
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return m;
}

}  // namespace softcut::mesh
