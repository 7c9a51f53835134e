// The second translation unit that includes CGAL's Mesh_3 (a polyhedral
// complex domain, ~3 GB and minutes to compile, like mesh_shape.cpp): every
// other file sees SurfaceDomain and TetMesh only.
#include "mesh/mesher/mesh_surface.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_polyhedron_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polyhedral_complex_mesh_domain_3.h>
#include <CGAL/Random.h>
#include <CGAL/exude_mesh_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/perturb_mesh_3.h>
#include <CGAL/refine_mesh_3.h>

#include <chrono>
#include <unordered_map>

#include "mesh/quality.hpp"

namespace softcut::mesh {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Polyhedron = CGAL::Mesh_polyhedron_3<K>::type;
using Domain = CGAL::Polyhedral_complex_mesh_domain_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;
using Point = K::Point_3;

// Dihedral angle between neighbouring surface triangles past which their
// edge is a sharp feature, protected by the mesher (CGAL's default).
constexpr double kFeatureAngleDeg = 60;

Eigen::Vector3d vec(const Point& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}; }

// h(p) (or a fraction of it) as a Mesh_3 sizing field.
struct SizeField {
  using FT = K::FT;
  using Point_3 = Point;
  using Index = Domain::Index;
  const MesherOptions* o;
  double scale;
  FT operator()(const Point& p, int, const Index&) const { return scale * local_size(*o, vec(p)); }
};

}  // namespace

TetMesh mesh_surface(const SurfaceDomain& d, const MesherOptions& o, MesherReport* report) {
  estimate_tets(d.shape, o);  // checks the options, naming the surface
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<Polyhedron> patches(d.shells.size());
  std::vector<std::pair<int, int>> sides;
  for (std::size_t s = 0; s < d.shells.size(); ++s) {
    const Shell& sh = d.shells[s];
    std::vector<Point> points;
    for (Eigen::Index i = 0; i < sh.points.rows(); ++i) points.emplace_back(sh.points(i, 0), sh.points(i, 1), sh.points(i, 2));
    std::vector<std::vector<std::size_t>> faces;
    for (Eigen::Index t = 0; t < sh.triangles.rows(); ++t)
      faces.push_back({std::size_t(sh.triangles(t, 0)), std::size_t(sh.triangles(t, 1)), std::size_t(sh.triangles(t, 2))});
    CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, faces, patches[s]);
    // (the subdomain behind the faces, the one their normals point to): the
    // domain's inside test returns .first where orientation(a, b, c, p) is
    // negative, i.e. behind a counter-clockwise face.
    sides.emplace_back(sh.inside, sh.outside);
  }
  CGAL::Random rng(o.seed);
  Domain domain(patches.begin(), patches.end(), sides.begin(), sides.end(), &rng);
  domain.detect_features(kFeatureAngleDeg);
  namespace p = CGAL::parameters;
  const Criteria criteria(p::edge_size = SizeField{&o, 1.0}, p::facet_angle = o.facet_angle_deg,
                          p::facet_size = SizeField{&o, 1.0}, p::facet_distance = SizeField{&o, o.facet_distance},
                          p::cell_radius_edge_ratio = o.radius_edge, p::cell_size = SizeField{&o, 1.0});
  CGAL::Mesh_error_code error = CGAL::CGAL_MESH_3_NO_ERROR;
  // What make_mesh_3 does, with seeds on every surface between its steps.
  // Its start protects the sharp edges and, where those leave too few
  // points, shoots random rays from the middle of the box: a lesion's
  // surface that no ray reaches (a 7 mm ball off-centre in a kidney) got no
  // point and came out as kidney. So each surface without sharp edges gets up
  // to 20 of its own vertices as seeds first (CGAL's
  // add_vertices_to_c3t3_on_patch_without_feature_edges, which make_mesh_3
  // does not call in 5.5; each surface with sharp edges is seeded by their
  // protection). C3t3_initializer is make_mesh_3's first step, in the
  // version Debian 12 ships.
  C3t3 c3t3;
  CGAL::Mesh_3::internal::C3t3_initializer<C3t3, Domain, Criteria,
                                            CGAL::Mesh_3::internal::has_Has_features<Domain>::value>()(
      c3t3, domain, criteria, /*with_features=*/true);
  domain.add_vertices_to_c3t3_on_patch_without_feature_edges(c3t3);
  // Refinement stops at the bounds; the optimisation passes run only when it finished (mesh_shape.cpp).
  CGAL::refine_mesh_3(c3t3, domain, criteria, p::no_lloyd(), p::no_odt(), p::no_perturb(), p::no_exude(),
                      p::no_reset_c3t3(),
                      p::mesh_3_options(p::maximal_number_of_vertices = o.max_vertices, p::pointer_to_error_code = &error,
                                        p::pointer_to_stop_atomic_boolean = const_cast<std::atomic<bool>*>(o.stop)));
  check_stopped(d.name, o, error == CGAL::CGAL_MESH_3_MAXIMAL_NUMBER_OF_VERTICES_REACHED);
  CGAL::perturb_mesh_3(c3t3, domain, p::time_limit = o.optimise_seconds, p::sliver_bound = o.sliver_bound_deg);
  CGAL::exude_mesh_3(c3t3, p::time_limit = o.optimise_seconds, p::sliver_bound = o.sliver_bound_deg);

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
  if (tets.empty()) fail(d.name, ": the mesher made no tetrahedra (is the body smaller than the cell size?)");
  TetMesh m;
  m.nodes.resize(Eigen::Index(nodes.size()), 3);
  for (std::size_t i = 0; i < nodes.size(); ++i) m.nodes.row(Eigen::Index(i)) = nodes[i].transpose();
  m.tets.resize(Eigen::Index(tets.size()), 4);
  m.labels.resize(Eigen::Index(tets.size()));
  for (std::size_t t = 0; t < tets.size(); ++t) m.tets.row(Eigen::Index(t)) = tets[t].transpose(), m.labels(Eigen::Index(t)) = labels[t];
  Diagnostics diag;
  validate(m, d.name, diag);
  if (report) {
    report->nodes = m.num_nodes();
    report->tets = m.num_tets();
    report->min_dihedral_deg = tet_quality(m).min_dihedral_deg;
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return m;
}

TetMesh generate_surface(const SurfaceDomain& d, const OrganOptions& o, const MeshLimit& limit, MesherReport* report) {
  return mesh_to_target(d.shape, o, limit, [&](const MesherOptions& m, MesherReport* r) { return mesh_surface(d, m, r); },
                        report);
}

}  // namespace softcut::mesh
